// Alarms need evidence AND a size that matters. Pins the size floor
// (AlarmParams::advisory_ratio), the spike bound (median-of-3 input of every CUSUM + the floor on the median
// of 5), the escalation of a rising channel through the operating-change rules (warning at x2, critical at x4
// of its reference, whatever a step rule adopted), and no false alarm from re-levelling on 12 correlated
// snapshots after a gap. Synthetic groups of four channels with 2 % log-level noise and oracle innovations
// (synthetic_group.hpp), plus a correlated plant for the gap case: the truth is how each stream was built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;
using namespace causal::alarms::test;

namespace {

std::vector<AlarmEvent> degradation_raises(const std::vector<AlarmEvent>& ev) {
  std::vector<AlarmEvent> out;
  for (const auto& e : ev)
    if (e.category == category::kDegradation && e.state == AlarmState::Raised) out.push_back(e);
  return out;
}

// A sustained rise of channel c by `ratio` (feature and oracle innovation) from observation `from` on.
void rise(std::vector<Observation>& obs, int c, int from, double ratio) {
  for (auto& o : obs)
    if (o.index >= static_cast<std::uint64_t>(from)) {
      o.features(c) *= ratio;
      if (o.index == static_cast<std::uint64_t>(from)) o.innovations(c) += std::log(ratio);
    }
}

AlarmEngine engine(const AlarmParams& p = AlarmParams{}) { return AlarmEngine("grp", channel_names4(), {}, p); }

}  // namespace

// +5 % sustained on a channel with 1 % noise (5 baseline sigma: statistically unambiguous) is below the +8 %
// floor: no alarm. The same stream without the floor alarms (the test can fail), and +12 % alarms with it.
TEST(AlarmSizeFloor, SignificantButSmallRiseDoesNotAlarm) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    cfg.sigma = 0.01;
    auto small = make_run(cfg);
    rise(small, 1, 300, 1.05);
    auto e = engine();
    const auto small_raises = degradation_raises(run_all(e, small));
    EXPECT_TRUE(small_raises.empty()) << "seed " << seed << ": " << small_raises.front().reason;
    AlarmParams no_floor;
    no_floor.advisory_ratio = 1.0;
    no_floor.baseline_tracking_observations = 0;
    auto e0 = engine(no_floor);
    EXPECT_FALSE(degradation_raises(run_all(e0, small)).empty()) << "seed " << seed << ": a +5 % step is 5 sigma";
    auto large = make_run(cfg);
    rise(large, 1, 300, 1.12);
    auto e1 = engine();
    const auto r = degradation_raises(run_all(e1, large));
    ASSERT_FALSE(r.empty()) << "seed " << seed;
    EXPECT_EQ(r.front().channel, 1);
    EXPECT_LE(r.front().index, 300u + 2u * static_cast<std::uint64_t>(AlarmParams{}.level_window)) << "seed " << seed;
  }
}

// One snapshot of +52 sigma (feature x2.8 and its innovation) raises nothing, on any detector, also when it
// lands on a channel whose CUSUM is already up (+3 %, 1.5 sigma, below the floor); nor does a +34 % jump that settles back after
// two snapshots.
TEST(AlarmSizeFloor, SingleSpikeAndJumpThatSettlesBackRaiseNothing) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    cfg.spike_at = 300;
    cfg.spike_channel = 2;
    cfg.spike_sigma = 52.0;
    auto obs = make_run(cfg);
    rise(obs, 2, 250, 1.03);
    for (auto& o : obs)
      if (o.index == 400 || o.index == 401) o.features(0) *= 1.34;
    auto e = engine();
    const auto r = degradation_raises(run_all(e, obs));
    EXPECT_TRUE(r.empty()) << "seed " << seed << ": " << r.front().kind << " " << r.front().reason;
  }
}

// A bearing that keeps rising in steps that each settle (+25 % every 40 snapshots, x4.8 in all) is followed
// as a level step once (within x1.5 of its reference), then alarmed as degradation, and escalates to warning
// and critical against its reference although a step rule adopted a higher level before.
TEST(AlarmSizeFloor, RisingChannelEscalatesThroughOperatingChanges) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    cfg.n = 700;
    auto obs = make_run(cfg);
    for (int k = 0; k < 7; ++k) rise(obs, 0, 250 + 40 * k, 1.25);
    auto e = engine();
    const auto ev = run_all(e, obs);
    Severity worst = Severity::Advisory;
    std::uint64_t first = 0;
    int steps_followed = 0;
    for (const auto& x : ev) {
      if (x.channel != 0) continue;
      if (x.kind == std::string(kind::kLevelStep) && x.state == AlarmState::Raised) ++steps_followed;
      if (x.category != category::kDegradation) continue;
      if (first == 0 && x.state == AlarmState::Raised) first = x.index;
      if (static_cast<int>(x.severity) > static_cast<int>(worst)) worst = x.severity;
    }
    EXPECT_EQ(worst, Severity::Critical) << "seed " << seed;
    ASSERT_GT(first, 0u) << "seed " << seed;
    EXPECT_LT(first, 250u + 40u * 2u + 20u) << "seed " << seed << ": the third step (x1.95) must alarm";
    EXPECT_LE(steps_followed, 1) << "seed " << seed;
    // A machine-wide step of the same size (every channel, settled) is a confirmed operating change.
    auto wide = make_run(cfg);
    for (int c = 0; c < 4; ++c) rise(wide, c, 250, 1.25);
    auto e2 = engine();
    const auto ev2 = run_all(e2, wide);
    EXPECT_TRUE(degradation_raises(ev2).empty()) << "seed " << seed;
    int confirmed = 0;
    for (const auto& x : ev2) confirmed += x.kind == std::string(kind::kOperatingChange) && x.state == AlarmState::Raised;
    EXPECT_EQ(confirmed, 4) << "seed " << seed;
  }
}

// A plant whose log levels wander slowly (AR(1), phi 0.97, sd 1 %, plus 1.5 % snapshot noise,
// about the spread of IMS test 2's healthy bearings: 12 snapshots are strongly correlated, so the level re-learned
// on them after a gap is off by a few percent) with gaps followed by
// +15-20 % level steps, 984 snapshots at 10 minutes: no degradation alarm on any healthy channel; every gap
// re-levelled. Without the size floor the same streams raised drift alarms (printed, the test can fail).
TEST(AlarmSizeFloor, NoFalseAlarmFromRelevellingAfterGap) {
  int without_floor = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nd(0.0, 1.0);
    std::uniform_real_distribution<double> step(1.15, 1.20);
    std::vector<Observation> obs;
    double ar[4] = {0, 0, 0, 0}, offset[4] = {0, 0, 0, 0};
    std::int64_t t_ns = kT0Ns;
    const int gaps[3] = {250, 450, 700};
    for (int t = 0; t < 984; ++t) {
      Observation o;
      o.index = static_cast<std::uint64_t>(t);
      for (int gap : gaps)
        if (t == gap) {
          t_ns += 30LL * 3600 * 1000000000LL;
          for (double& x : offset) x += std::log(step(rng));
        }
      o.time_ns = t_ns;
      t_ns += kStepNs;
      o.features.resize(4);
      o.innovations.resize(4);
      o.innovation_variances = Eigen::VectorXd::Constant(4, 0.015 * 0.015);
      for (int c = 0; c < 4; ++c) {
        const double shock = 0.015 * nd(rng);
        ar[c] = 0.97 * ar[c] + 0.0024 * nd(rng);  // slow wander, stationary sd 1 %
        o.features(c) = std::exp(std::log(0.07) + offset[c] + ar[c] + shock);
        o.innovations(c) = shock;
      }
      obs.push_back(std::move(o));
    }
    auto e = engine();
    const auto ev = run_all(e, obs);
    const auto r = degradation_raises(ev);
    std::string changes;
    for (const auto& x : ev)
      if (x.category != category::kDegradation && x.state == AlarmState::Raised) changes += "\n  " + x.reason;
    EXPECT_TRUE(r.empty()) << "seed " << seed << ": " << r.front().reason << changes;
    int relevelled = 0;
    for (const auto& x : ev) relevelled += x.kind == std::string(kind::kDiscontinuity) && x.state == AlarmState::Raised;
    EXPECT_GE(relevelled, 8) << "seed " << seed;  // 3 gaps x 4 channels, minus channels caught trending
    AlarmParams no_floor;
    no_floor.advisory_ratio = 1.0;
    no_floor.baseline_tracking_observations = 0;
    auto e0 = engine(no_floor);
    without_floor += static_cast<int>(degradation_raises(run_all(e0, obs)).size());
  }
  std::printf("gap re-levelling, 20 plants: degradation alarms without the size floor: %d, with it: 0\n", without_floor);
}
