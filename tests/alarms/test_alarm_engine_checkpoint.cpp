// AlarmEngine checkpoints (crash and restart safety). The truth every test compares with is the SAME
// engine run over the same stream without interruption: an engine saved at a cut point, restored into a
// fresh object and fed the rest of the stream must emit exactly the same events (every field, ids
// included), hold the same active alarms and report the same diagnostics after every observation.
// Streams: the synthetic group (synthetic_group.hpp, with a ramp fault that raises, escalates, clears and
// raises again) and the real IMS test-2 condition stream of causal-alarm-eval (causal Kalman filter on the
// mean |x| feature table shipped in deploy/data), cut during warm-up, baseline, quiet monitoring, while an
// alarm is active or escalating, and after a clear.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "causal/alarms/alarm_pipeline.hpp"
#include "causal/alarms/alarm_engine.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/svar_layout.hpp"
#include "same_fields.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;
using causal::estimation::StateError;
using causal::estimation::StateReader;
using causal::estimation::StateWriter;

namespace {

// Bit-identical doubles (NaN equals NaN: "no value" must stay "no value").
bool same(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }
bool same(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}

void expect_same_event(const AlarmEvent& a, const AlarmEvent& b, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_SAME_FIELDS(a, b, alarm_id, channel, severity, state, kind, raised_time_ns, cleared_time_ns, index,
                     onset_index, onset_time_ns, root_cause_channel, factor_names, reason);
  EXPECT_TRUE(same(a.factor_baseline, b.factor_baseline)) << where;
  EXPECT_TRUE(same(a.factor_now, b.factor_now)) << where;
  EXPECT_TRUE(same(a.score, b.score)) << where << ": " << a.score << " vs " << b.score;
  EXPECT_TRUE(same(a.threshold, b.threshold)) << where;
}

void expect_same_signal(const SignalDiagnostics& a, const SignalDiagnostics& b, const std::string& where) {
  EXPECT_EQ(a.monitored, b.monitored) << where;
  EXPECT_TRUE(same(a.baseline_location, b.baseline_location)) << where;
  EXPECT_TRUE(same(a.baseline_scale, b.baseline_scale)) << where;
  EXPECT_TRUE(same(a.baseline_lag1_autocorr, b.baseline_lag1_autocorr)) << where;
  EXPECT_TRUE(same(a.last_z, b.last_z)) << where;
  EXPECT_TRUE(same(a.cusum, b.cusum)) << where;
}

// Everything an engine reports from outside, compared between the uninterrupted and the restored engine.
void expect_same_engine(const AlarmEngine& a, const AlarmEngine& b, const std::string& where) {
  EXPECT_EQ(a.observations_seen(), b.observations_seen()) << where;
  EXPECT_EQ(a.rejected_observations(), b.rejected_observations()) << where;
  EXPECT_EQ(a.not_running_observations(), b.not_running_observations()) << where;
  EXPECT_EQ(a.baseline_ready(), b.baseline_ready()) << where;
  for (int c = 0; c < a.channel_count(); ++c) {
    const auto da = a.channel_diagnostics(c), db = b.channel_diagnostics(c);
    const std::string w = where + " channel " + std::to_string(c);
    expect_same_signal(da.feature, db.feature, w + " feature");
    expect_same_signal(da.innovation, db.innovation, w + " innovation");
    EXPECT_TRUE(same(da.nis_window_mean, db.nis_window_mean)) << w;
    EXPECT_TRUE(same(da.factor_max_abs_z, db.factor_max_abs_z)) << w;
    EXPECT_EQ(da.monitored_factors, db.monitored_factors) << w;
    EXPECT_EQ(da.rejected_values, db.rejected_values) << w;
    EXPECT_EQ(da.root_cause, db.root_cause) << w;
  }
  const auto aa = a.active_alarms(), ab = b.active_alarms();
  ASSERT_EQ(aa.size(), ab.size()) << where;
  for (std::size_t i = 0; i < aa.size(); ++i) expect_same_event(aa[i], ab[i], where + " active alarm");
}

std::string checkpoint_of(const AlarmEngine& e) {
  causal::estimation::StateWriter w;
  e.save(w);
  return w.bytes();
}

struct Stream {
  std::string group;
  std::vector<std::string> channels, factors;
  AlarmParams params;
  std::vector<Observation> obs;
};

AlarmEngine fresh(const Stream& s) { return AlarmEngine(s.group, s.channels, s.factors, s.params); }

std::vector<AlarmEvent> uninterrupted(const Stream& s) {
  auto e = fresh(s);
  std::vector<AlarmEvent> all;
  for (const auto& o : s.obs)
    for (auto& ev : e.observe(o)) all.push_back(std::move(ev));
  return all;
}

// Runs the stream through an engine that is saved and restored into a fresh object before observation t
// for every t in `cuts` (through a checkpoint file when `via_file`), side by side with an uninterrupted
// engine; compares events and the engines' state after every observation. Returns the restored run's events.
std::vector<AlarmEvent> run_with_cuts(const Stream& s, const std::set<std::size_t>& cuts, const std::string& label,
                                      bool via_file = false) {
  auto reference = fresh(s);
  auto engine = fresh(s);
  std::vector<AlarmEvent> all;
  // One file per process and test: ctest -j runs the tests of this binary side by side.
  const std::string file = ::testing::TempDir() + "alarm_engine_checkpoint_" + std::to_string(::getpid()) + "_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".state";
  for (std::size_t t = 0; t < s.obs.size(); ++t) {
    if (cuts.count(t) > 0) {
      std::string bytes = checkpoint_of(engine);
      if (via_file) {
        causal::estimation::save_state_file(file, bytes);
        bytes = causal::estimation::load_state_file(file).value();
      }
      causal::estimation::StateReader in(bytes);
      engine = AlarmEngine::restore(in, s.params);  // the old object is gone: nothing survives but the bytes
      EXPECT_TRUE(in.at_end()) << label << " cut " << t;
    }
    const auto expected = reference.observe(s.obs[t]);
    const auto got = engine.observe(s.obs[t]);
    const std::string where = label + " observation " + std::to_string(t);
    EXPECT_EQ(got.size(), expected.size()) << where;
    for (std::size_t i = 0; i < std::min(got.size(), expected.size()); ++i) expect_same_event(got[i], expected[i], where);
    expect_same_engine(reference, engine, where);
    if (::testing::Test::HasFatalFailure()) break;
    all.insert(all.end(), got.begin(), got.end());
  }
  std::filesystem::remove(file);
  return all;
}

std::size_t first_index_of(const std::vector<AlarmEvent>& ev, AlarmState state) {
  for (const auto& e : ev)
    if (e.state == state) return static_cast<std::size_t>(e.index);
  return 0;
}

// Channel 2's own noise ramps up from t = 400 (0.5 sigma per observation, to 20 sigma) and is back to normal
// at 440; a second, shorter fault on the same channel at 520..540 raises the same kinds again.
Stream synthetic_stream(bool with_factors, std::uint64_t seed = 3) {
  test::SyntheticConfig cfg;
  cfg.seed = seed;
  cfg.with_factors = with_factors;
  cfg.own_change = [](int t) {
    if (t >= 400 && t < 440) return 0.5 * (t - 400);
    if (t >= 520 && t < 540) return 8.0;
    return 0.0;
  };
  Stream s;
  s.group = "grp";
  s.channels = test::channel_names4();
  s.obs = test::make_run(cfg);
  // The 8-sigma (+16 %) second fault is a sustained step: kept a fault here (the operating-change rule and
  // its checkpoint have their own tests in test_alarm_operating_changes.cpp).
  s.params.operating_step_ratio = 1e3;
  // Severities follow the channel's level (x1.49 at the top of the ramp): a warning level it crosses, so the
  // stream holds an escalation to cut at.
  s.params.warning_ratio = 1.3;
  s.params.max_absorbed_ratio = 1.2;
  if (with_factors) {
    // Exercise the factor detector's state as well: x23 (channel 2's dependence on 3) leaves its baseline
    // by 30 of its standard deviations during the first fault.
    s.factors = test::factor_names4();
    s.params.factor_enabled = true;
    const auto x23 = std::find(s.factors.begin(), s.factors.end(), "x23") - s.factors.begin();
    for (int t = 400; t < 440; ++t) s.obs[static_cast<std::size_t>(t)].factors(x23) += 0.3;
  }
  return s;
}

// The cut points of the brief, located in the uninterrupted run (so they stay meaningful if the stream
// changes): warm-up, baseline, quiet monitoring, inside the excursion that is about to raise, alarm just
// raised, just before an escalation, just after the first clear.
std::set<std::size_t> cut_points(const Stream& s, const std::vector<AlarmEvent>& ref) {
  const auto warm = static_cast<std::size_t>(s.params.warmup_observations);
  const auto base = static_cast<std::size_t>(s.params.baseline_observations);
  const std::size_t raised = first_index_of(ref, AlarmState::Raised);
  const std::size_t escalated = first_index_of(ref, AlarmState::Escalated);
  const std::size_t cleared = first_index_of(ref, AlarmState::Cleared);
  std::set<std::size_t> cuts = {warm / 2, warm + base / 2, warm + base - 1, warm + base, (warm + base + raised) / 2};
  if (raised > 0) cuts.insert({raised - 1, raised, raised + 1});  // inside the CUSUM excursion, at, after the raise
  if (escalated > 0) cuts.insert(escalated);
  if (cleared > 0) cuts.insert(cleared + 1);
  return cuts;
}

}  // namespace

TEST(AlarmEngineCheckpoint, SyntheticStreamSurvivesEveryCutPoint) {
  for (bool with_factors : {false, true}) {
    const Stream s = synthetic_stream(with_factors);
    const auto ref = uninterrupted(s);
    // The scenario must contain what the cuts are about, else the test proves nothing.
    ASSERT_GT(first_index_of(ref, AlarmState::Raised), 0u);
    ASSERT_GT(first_index_of(ref, AlarmState::Escalated), 0u);
    ASSERT_GT(first_index_of(ref, AlarmState::Cleared), 0u);
    if (with_factors) {
      ASSERT_TRUE(std::any_of(ref.begin(), ref.end(), [](const AlarmEvent& e) { return e.kind == kind::kFactorShift; }));
    }
    const auto cuts = cut_points(s, ref);
    const std::string label = with_factors ? "factors" : "no factors";
    for (std::size_t cut : cuts) {
      const auto got = run_with_cuts(s, {cut}, label + " cut " + std::to_string(cut));
      EXPECT_EQ(got.size(), ref.size()) << label << " cut " << cut;
    }
    const auto got = run_with_cuts(s, cuts, label + " all cuts", /*via_file=*/true);
    EXPECT_EQ(got.size(), ref.size()) << label;
  }
}

// Sample-level configuration: the innovation signal is log mean NIS (another baseline path) and the NIS
// window is 4 publications.
TEST(AlarmEngineCheckpoint, SampleLevelStreamSurvivesCuts) {
  Stream s = synthetic_stream(false);
  s.params = AlarmParams::sample_level(50);
  for (auto& o : s.obs) {
    o.mean_nis.resize(4);
    for (int k = 0; k < 4; ++k) o.mean_nis(k) = 0.5 + o.innovations(k) * o.innovations(k) / o.innovation_variances(k);
  }
  const auto ref = uninterrupted(s);
  ASSERT_GT(first_index_of(ref, AlarmState::Raised), 0u);
  const auto got = run_with_cuts(s, cut_points(s, ref), "sample level");
  EXPECT_EQ(got.size(), ref.size());
}

// The real stream: IMS test 2 through the services' chain of causal-alarm-eval (the estimator's
// condition-level filter with the shipped estimator.yaml, filter innovations, shipped alarm parameters). The pipeline's own engine is the uninterrupted run.
TEST(AlarmEngineCheckpoint, Ims2ConditionStreamSurvivesCuts) {
  std::string path = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "IMS test-2 feature table not found at " << path;
  auto opt = causal::alarms::shipped_options("ims2");
  Stream s;
  opt.on_observation = [&](const Observation& o) { s.obs.push_back(o); };
  const auto series = causal::alarms::series_from_feature_table(path, "meanabs");
  const auto pipeline = causal::alarms::run_condition_pipeline(series, opt);
  s.group = opt.asset_group;
  s.channels = series.channel_names;
  s.params = opt.params;
  s.factors = pipeline.factor_names;  // the estimator's condition-level model (shipped estimator.yaml)
  ASSERT_EQ(s.obs.size(), 984u);
  ASSERT_EQ(static_cast<std::size_t>(s.obs.front().factors.size()), s.factors.size());
  const auto ref = uninterrupted(s);
  ASSERT_EQ(ref.size(), pipeline.events.size()) << "the replayed stream must be the pipeline's";
  for (std::size_t i = 0; i < ref.size(); ++i) expect_same_event(ref[i], pipeline.events[i], "replay");
  ASSERT_GT(first_index_of(ref, AlarmState::Raised), 500u);
  const auto cuts = cut_points(s, ref);
  const auto got = run_with_cuts(s, cuts, "ims2", /*via_file=*/true);
  ASSERT_EQ(got.size(), pipeline.events.size());
  RecordProperty("ims2_cuts", static_cast<int>(cuts.size()));
  RecordProperty("ims2_events", static_cast<int>(got.size()));
}

// Alarm ids are "<group>/<channel>/<kind>/<counter>" and never reused: the counter is part of the state.
// Cut after the first alarm has cleared; the next raise of the same (channel, kind) must get counter 2.
TEST(AlarmEngineCheckpoint, AlarmIdsAreNotReusedAfterRestore) {
  const Stream s = synthetic_stream(false);
  const auto ref = uninterrupted(s);
  std::size_t cut = 0;
  std::string first_id;
  for (const auto& e : ref)
    if (e.state == AlarmState::Cleared && e.kind == kind::kFeatureDrift && e.channel == 1) {
      cut = static_cast<std::size_t>(e.index) + 1;
      first_id = e.alarm_id;
      break;
    }
  ASSERT_EQ(first_id, "grp/2/feature_drift/1");
  auto before = fresh(s);
  for (std::size_t t = 0; t < cut; ++t) before.observe(s.obs[t]);
  causal::estimation::StateReader in(checkpoint_of(before));
  auto after = AlarmEngine::restore(in, s.params);
  std::set<std::string> raised_ids;
  for (const auto& e : ref)
    if (e.state == AlarmState::Raised && e.index < cut) raised_ids.insert(e.alarm_id);
  const AlarmEvent* next = nullptr;
  std::vector<AlarmEvent> later;
  for (std::size_t t = cut; t < s.obs.size(); ++t)
    for (auto& e : after.observe(s.obs[t])) later.push_back(std::move(e));
  for (const auto& e : later) {
    if (e.state != AlarmState::Raised) continue;
    EXPECT_EQ(raised_ids.count(e.alarm_id), 0u) << "id reused after restore: " << e.alarm_id;
    raised_ids.insert(e.alarm_id);
    if (next == nullptr && e.kind == kind::kFeatureDrift && e.channel == 1) next = &e;
  }
  ASSERT_NE(next, nullptr) << "the second fault must raise feature_drift on channel 2 again";
  EXPECT_EQ(next->alarm_id, "grp/2/feature_drift/2");
}

TEST(AlarmEngineCheckpoint, TruncatedCheckpointThrowsStateError) {
  const Stream s = synthetic_stream(true);
  auto e = fresh(s);
  for (std::size_t t = 0; t < 410; ++t) e.observe(s.obs[t]);  // baseline learned, fault under way
  const std::string bytes = checkpoint_of(e);
  ASSERT_GT(bytes.size(), 1000u);
  // Every proper prefix (sampled every 7 bytes, plus the last byte missing) must be refused cleanly.
  for (std::size_t n = 0; n < bytes.size(); n += n + 7 < bytes.size() ? 7 : std::max<std::size_t>(1, bytes.size() - 1 - n)) {
    causal::estimation::StateReader in(bytes.substr(0, n));
    EXPECT_THROW(AlarmEngine::restore(in, s.params), causal::estimation::StateError) << "prefix of " << n << " bytes";
  }
  causal::estimation::StateReader whole(bytes);
  EXPECT_NO_THROW(AlarmEngine::restore(whole, s.params));
}

TEST(AlarmEngineCheckpoint, WrongTagThrowsStateError) {
  causal::estimation::StateWriter w;
  w.begin("svar_kalman_filter", 1);
  w.put(std::string("not an alarm engine"));
  causal::estimation::StateReader in(w.bytes());
  try {
    AlarmEngine::restore(in, AlarmParams{});
    FAIL() << "a foreign checkpoint was accepted";
  } catch (const causal::estimation::StateError& e) {
    EXPECT_NE(std::string(e.what()).find("'alarm_engine'"), std::string::npos) << e.what();
  }
  // A right tag with another version is refused as well.
  causal::estimation::StateWriter v;
  v.begin("alarm_engine", 99);
  causal::estimation::StateReader vin(v.bytes());
  EXPECT_THROW(AlarmEngine::restore(vin, AlarmParams{}), causal::estimation::StateError);
}

TEST(AlarmEngineCheckpoint, OtherParamsThrowStateErrorNamingThem) {
  const Stream s = synthetic_stream(false);
  auto e = fresh(s);
  for (std::size_t t = 0; t < 200; ++t) e.observe(s.obs[t]);
  const std::string bytes = checkpoint_of(e);
  AlarmParams other = s.params;
  other.cusum_k = 2.0;
  other.clear_persistence = 6;
  causal::estimation::StateReader in(bytes);
  try {
    AlarmEngine::restore(in, other);
    FAIL() << "a checkpoint of other parameters was accepted";
  } catch (const causal::estimation::StateError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("cusum_k: 1.5 -> 2"), std::string::npos) << what;
    EXPECT_NE(what.find("clear_persistence: 12 -> 6"), std::string::npos) << what;
    EXPECT_EQ(what.find("warmup_observations"), std::string::npos) << "only differences are named: " << what;
  }
  // Without expected parameters the checkpoint's own are used.
  causal::estimation::StateReader own(bytes);
  const auto restored = AlarmEngine::restore(own);
  EXPECT_EQ(param_differences(restored.params(), s.params), "");
  EXPECT_EQ(restored.observations_seen(), 200u);
  EXPECT_EQ(restored.asset_group(), "grp");
  EXPECT_EQ(restored.channel_names(), s.channels);
}
