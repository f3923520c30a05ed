// Input the twin lost is not a recording gap (src/input_continuity.hpp): a consecutively numbered source whose
// indices skip a range gives one HEALTH event "input_lost" naming it (raised and cleared at once), and never a
// "recording resumed after a gap" operating change; a time jump between consecutive indices still is one.
// Synthetic groups of four channels (synthetic_group.hpp: one observation per 10 min from 2004-02-12 10:32:39),
// and the real IMS test-2 run through the services' chain with the range a killed estimator lost.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "causal/alarms/alarm_pipeline.hpp"
#include "causal/alarms/alarm_engine.hpp"
#include "causal/estimation/state_archive.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;
using namespace causal::alarms::test;

namespace {

AlarmEngine make_engine() { return AlarmEngine("grp", channel_names4(), {}, AlarmParams{}); }

std::vector<AlarmEvent> of_category(const std::vector<AlarmEvent>& ev, const std::string& category) {
  std::vector<AlarmEvent> out;
  for (const auto& e : ev)
    if (e.category == category) out.push_back(e);
  return out;
}

// The run without the observations whose index is in [first, last].
std::vector<Observation> without(const std::vector<Observation>& obs, std::uint64_t first, std::uint64_t last) {
  std::vector<Observation> out;
  for (const auto& o : obs)
    if (o.index < first || o.index > last) out.push_back(o);
  return out;
}

void expect_lost_event(const std::vector<AlarmEvent>& health, const std::string& id, std::uint64_t first,
                       std::uint64_t last, std::uint64_t at, const std::string& text) {
  ASSERT_EQ(health.size(), 2u);
  for (const auto& e : health) {
    EXPECT_EQ(e.alarm_id, id);
    EXPECT_EQ(e.kind, kind::kInputLost);
    EXPECT_EQ(e.channel, -1);
    EXPECT_EQ(e.severity, Severity::Warning);
    EXPECT_EQ(e.index, at);
    EXPECT_EQ(e.onset_index, first);
    EXPECT_EQ(e.score, static_cast<double>(last - first + 1));
    EXPECT_EQ(e.raised_time_ns, kT0Ns + static_cast<std::int64_t>(at) * kStepNs);
    EXPECT_EQ(e.onset_time_ns, kT0Ns + static_cast<std::int64_t>(first - 1) * kStepNs);
    EXPECT_EQ(e.reason.rfind(text, 0), 0u) << e.reason;
  }
  EXPECT_EQ(health[0].state, AlarmState::Raised);
  EXPECT_EQ(health[1].state, AlarmState::Cleared);
  EXPECT_EQ(health[1].cleared_time_ns, health[1].raised_time_ns);
}

}  // namespace

// 40 observations (300..339, 6.7 h at 10 min) never arrive; the first one after them may carry the discontinuity
// flag (the estimator flags the first vector after lost frames, so no lag spans the hole). One input_lost event at
// 340, nothing else: no discontinuity, no operating change, no degradation, on ten healthy runs.
TEST(AlarmInputLost, SkippedIndicesAreLostInputNotAGap) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    for (const bool flagged : {false, true}) {
      SyntheticConfig cfg;
      cfg.seed = seed;
      auto obs = without(make_run(cfg), 300, 339);
      obs[300].discontinuity = flagged;
      ASSERT_EQ(obs[300].index, 340u);
      auto e = make_engine();
      const auto ev = run_all(e, obs);
      const std::string where = "seed " + std::to_string(seed) + (flagged ? " flagged" : "");
      EXPECT_TRUE(of_category(ev, category::kOperatingChange).empty()) << where << ": " << ev.front().reason;
      EXPECT_TRUE(of_category(ev, category::kDegradation).empty()) << where << ": " << ev.front().reason;
      ASSERT_EQ(ev.size(), 2u) << where;
      expect_lost_event(of_category(ev, category::kHealth), "grp/observations/input_lost/1", 300, 339, 340,
                        "40 observations never reached the alarm engine (observations 300..339, between "
                        "2004-02-14 12:22:39 UTC and 2004-02-14 19:12:39 UTC): the twin lost this input");
      EXPECT_EQ(e.lost_observations(), 40u);
      EXPECT_EQ(e.input_losses(), 1u);
      EXPECT_EQ(e.discontinuities(), 0u);
      EXPECT_EQ(e.operating_changes(), 0u);
    }
  }
}

// The same loss with the recording also paused for 2 days inside it: the time beyond what 40 lost observations
// span is a gap (3 x the usual interval per observation that should have come), so both are reported: input_lost
// at 340, and each channel's "recording resumed after a gap of 2.3 days" at the end of the confirmation window.
TEST(AlarmInputLost, PauseBeyondTheLostObservationsIsStillAGap) {
  SyntheticConfig cfg;
  cfg.seed = 3;
  auto obs = without(make_run(cfg), 300, 339);
  for (auto& o : obs)
    if (o.index >= 340) o.time_ns += 2LL * 86400 * 1000000000LL;
  auto e = make_engine();
  const auto ev = run_all(e, obs);
  const auto health = of_category(ev, category::kHealth);
  ASSERT_EQ(health.size(), 2u);
  EXPECT_EQ(health[0].onset_index, 300u);
  EXPECT_EQ(health[0].index, 340u);
  const auto oc = of_category(ev, category::kOperatingChange);
  ASSERT_EQ(oc.size(), 8u);  // 4 channels x (raised, cleared)
  for (const auto& x : oc) {
    EXPECT_EQ(x.kind, kind::kDiscontinuity);
    EXPECT_EQ(x.onset_index, 340u);
    EXPECT_NE(x.reason.find("after a gap of 2.3 days"), std::string::npos) << x.reason;
  }
  EXPECT_EQ(e.discontinuities(), 1u);
  EXPECT_TRUE(of_category(ev, category::kDegradation).empty());
}

// A source that does not number consecutively (every 4th snapshot; sample-level publications) skips by design:
// a larger step is never taken for lost input. Here the step is 4 and one step of 8 follows: nothing reported.
TEST(AlarmInputLost, SubsampledSourceIsNotJudged) {
  SyntheticConfig cfg;
  cfg.seed = 5;
  auto obs = make_run(cfg);
  for (auto& o : obs) o.index *= 4;
  obs.erase(obs.begin() + 400);
  auto e = make_engine();
  const auto ev = run_all(e, obs);
  EXPECT_TRUE(of_category(ev, category::kHealth).empty());
  EXPECT_EQ(e.lost_observations(), 0u);
}

// Lost while the baseline is still being learned (observations 100..119 of warm-up 20 + baseline 120): reported
// at once, and the baseline goes on with the observations that came.
TEST(AlarmInputLost, LossDuringTheBaselineIsReported) {
  SyntheticConfig cfg;
  cfg.seed = 7;
  auto e = make_engine();
  const auto ev = run_all(e, without(make_run(cfg), 100, 119));
  expect_lost_event(of_category(ev, category::kHealth), "grp/observations/input_lost/1", 100, 119, 120,
                    "20 observations never reached the alarm engine (observations 100..119, between "
                    "2004-02-13 03:02:39 UTC and 2004-02-13 06:32:39 UTC)");
  EXPECT_TRUE(e.baseline_ready());
  EXPECT_EQ(ev.size(), 2u);
}

// Checkpoints keep the last index and the loss count (alarm_index_continuity): an engine restored after the first
// loss and fed the rest gives exactly the events of the one that never stopped, the second loss numbered 2.
TEST(AlarmInputLost, CheckpointKeepsTheLastIndexAndTheCount) {
  SyntheticConfig cfg;
  cfg.seed = 2;
  const auto obs = without(without(make_run(cfg), 300, 339), 450, 450);
  auto whole = make_engine();
  const auto expected = run_all(whole, obs);
  auto first = make_engine();
  std::vector<AlarmEvent> got;
  std::size_t i = 0;
  for (; obs[i].index <= 400; ++i)
    for (auto& ev : first.observe(obs[i])) got.push_back(std::move(ev));
  causal::estimation::StateWriter w;
  first.save(w);
  causal::estimation::StateReader r(w.bytes());
  auto restored = AlarmEngine::restore(r, AlarmParams{});
  for (; i < obs.size(); ++i)
    for (auto& ev : restored.observe(obs[i])) got.push_back(std::move(ev));
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].alarm_id, expected[k].alarm_id);
    EXPECT_EQ(got[k].reason, expected[k].reason);
  }
  const auto health = of_category(got, category::kHealth);
  ASSERT_EQ(health.size(), 4u);
  EXPECT_EQ(health[2].alarm_id, "grp/observations/input_lost/2");
  EXPECT_EQ(health[2].onset_index, 450u);
  EXPECT_EQ(health[2].index, 451u);
  EXPECT_EQ(health[2].reason.rfind("1 observation never reached the alarm engine (observation 450, ", 0), 0u);
  EXPECT_EQ(restored.lost_observations(), 41u);
  EXPECT_EQ(restored.input_losses(), 2u);
}

// The real case (IMS test 2, the services' chain): an estimator killed at snapshot 620 of 984 and back beyond the
// source's backlog lost 621..802 (30 h of plant time). The recording shows one input_lost event naming the range,
// and every operating-change and degradation event of the undisturbed run before the loss, none inside it; the
// bearing-1 alarm raised before the loss stays open across it.
TEST(AlarmInputLost, Ims2RunWithTheRangeAKilledEstimatorLost) {
  const std::string dir = std::string(CAUSAL_TWIN_SHARED_DIR) + "/data/ims2/derived_per_file_stats_all984.csv";
  const std::string path = std::filesystem::exists(dir)
                               ? dir
                               : std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "IMS test-2 feature table not found at " << path;
  const ConditionSeries full = series_from_feature_table(path, "meanabs");
  ConditionSeries cut = full;
  cut.time_ns.clear();
  cut.index.clear();
  cut.discontinuity.clear();
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < full.index.size(); ++i) {
    if (full.index[i] >= 621 && full.index[i] <= 802) continue;
    rows.push_back(static_cast<Eigen::Index>(i));
    cut.time_ns.push_back(full.time_ns[i]);
    cut.index.push_back(full.index[i]);
    cut.discontinuity.push_back(full.index[i] == 803 || full.discontinuity[i]);  // as the estimator flags it
  }
  cut.values.resize(static_cast<Eigen::Index>(rows.size()), full.values.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) cut.values.row(static_cast<Eigen::Index>(k)) = full.values.row(rows[k]);

  const PipelineOptions opt = shipped_options("ims2");
  const PipelineResult a = run_condition_pipeline(full, opt);
  const PipelineResult b = run_condition_pipeline(cut, opt);
  EXPECT_EQ(b.input_losses, 1u);
  EXPECT_EQ(b.observations + 182u, a.observations);
  std::vector<AlarmEvent> lost, before_a, before_b;
  for (const auto& e : a.events)
    if (e.index <= 620) before_a.push_back(e);
  for (const auto& e : b.events) {
    if (e.category == category::kHealth) lost.push_back(e);
    else if (e.index <= 620) before_b.push_back(e);
    // Nothing from the lost range is reported as a change of the machine.
    if (e.category == category::kOperatingChange) {
      EXPECT_TRUE(e.onset_index < 621 || e.onset_index > 802) << e.reason;
      EXPECT_NE(e.kind, kind::kDiscontinuity) << e.reason;
    }
  }
  ASSERT_EQ(lost.size(), 2u);
  EXPECT_EQ(lost[0].alarm_id, "ims2/observations/input_lost/1");
  EXPECT_EQ(lost[0].index, 803u);
  EXPECT_EQ(lost[0].reason.rfind("182 observations never reached the alarm engine (observations 621..802, ", 0), 0u)
      << lost[0].reason;
  ASSERT_EQ(before_b.size(), before_a.size());
  for (std::size_t k = 0; k < before_a.size(); ++k) EXPECT_EQ(before_b[k].alarm_id, before_a[k].alarm_id);
  ASSERT_TRUE(b.summary[0].alarmed);
  EXPECT_LE(b.summary[0].first.index, 547u);
  EXPECT_EQ(b.summary[0].first_cleared_index, 0u) << "the bearing-1 alarm must stay open across the loss";
}
