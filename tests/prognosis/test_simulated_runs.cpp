// The prognosis as alarm-recommender runs it (alarm engine + channel trends) on simulated run-to-failure
// channels with known crossing times (causal-prognosis-eval's simulator): the healthy channel gets no
// prognosis, the wearing one does, and it is ahead of both anchors (Theil-Sen with bootstrap intervals,
// random walk with drift; and the conformal row) in point accuracy, and in coverage wherever an anchor's intervals
// are informative.
#include "prognosis_scoring.hpp"
#include "prognosis_anchors.hpp"
#include "prognosis_conformal.hpp"
#include "run_to_failure_sim.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

using namespace causal;
using namespace causal::prognosis_eval;

TEST(SimulatedRuns, TwinIsAheadOfBothAnchors) {
  std::array<MethodScores, kMethods> all;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    SimSpec spec;
    spec.seed = seed;
    spec.gaussian = seed % 2 == 0;
    const SimRun run = simulate_run_to_failure(spec);
    ASSERT_GT(run.crossing_ns(4.0), run.crossing_ns(2.0));
    ASSERT_LE(run.crossing_ns(6.0), run.stop_ns);
    const PrognosisScorer s = score_simulated_run(run, prognosis::PrognosisParams{});
    ASSERT_GE(s.first_alarm_index(), static_cast<std::int64_t>(spec.healthy_rows)) << "seed " << seed;
    for (const auto& e : s.engine().active_alarms()) EXPECT_NE(e.channel, 1) << "healthy channel alarmed: " << e.alarm_id;
    for (int m = 0; m < kMethods; ++m) all[static_cast<std::size_t>(m)].merge(s.scores()[static_cast<std::size_t>(m)]);
  }
  auto coverage = [](const LevelScore& s) { return static_cast<double>(s.covered) / std::max(1.0, static_cast<double>(s.known)); };
  auto median_width = [](LevelScore s) {
    if (s.rel_widths.empty()) return std::numeric_limits<double>::infinity();
    auto mid = s.rel_widths.begin() + static_cast<std::ptrdiff_t>(s.rel_widths.size() / 2);
    std::nth_element(s.rel_widths.begin(), mid, s.rel_widths.end());
    return *mid;
  };
  // The target: 90 % intervals that hold the actual time in >= 80 % of the answers while their median width is
  // at most 1.5 x the remaining time. An interval many times the remaining time covers by being uninformative
  // (the random walk's are 9-14 x here), so an anchor is ahead on coverage only with intervals within that width.
  constexpr double kMaxMedianWidth = 1.5;
  for (int l = 0; l < kLevels; ++l) {
    const auto& t = all[0].level[static_cast<std::size_t>(l)];
    ASSERT_GT(t.decisions, 100u);
    ASSERT_GT(t.known, 10u) << "level " << l;
    EXPECT_GE(coverage(t), 0.8) << "level " << l;
    EXPECT_LE(median_width(t), kMaxMedianWidth) << "level " << l;
    for (int m = 1; m < kMethods; ++m) {
      const auto& a = all[static_cast<std::size_t>(m)].level[static_cast<std::size_t>(l)];
      ASSERT_EQ(a.decisions, t.decisions) << "the anchors are scored at the same decision points";
      if (median_width(a) <= kMaxMedianWidth) EXPECT_GT(coverage(t), coverage(a)) << method_name(m) << " level " << l;
      EXPECT_GT(t.within_30, a.within_30) << method_name(m) << " level " << l;
    }
  }
}

// The anchors on data whose answer is known in closed form.
TEST(SimulatedRuns, AnchorsOnAStraightLine) {
  std::vector<double> t, y;
  for (int i = 0; i <= 60; ++i) {
    t.push_back(i / 6.0);              // 10 h at 10-min spacing
    y.push_back(0.05 * t.back());      // log level rising 0.05 per hour, no noise
  }
  // Theil-Sen: every bootstrap fit is the line itself, so the interval collapses on (log 2 - 0.5) / 0.05 h.
  const Prediction ts = TheilSenBootstrap(t, y, 200, 7).time_to(std::log(2.0), 0.9);
  ASSERT_TRUE(ts.known) << ts.why;
  const double exact = (std::log(2.0) - 0.5) / 0.05;
  EXPECT_NEAR(ts.hours, exact, 1e-9);
  EXPECT_NEAR(ts.low, exact, 1e-9);
  EXPECT_NEAR(ts.high, exact, 1e-9);
  EXPECT_TRUE(TheilSenBootstrap(t, y, 200, 7).time_to(0.4, 0.9).reached);
  // Falling data: no answer from either anchor.
  std::vector<double> down(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) down[i] = -y[i] + 0.01 * (static_cast<double>(i % 3) - 1.0);
  EXPECT_FALSE(TheilSenBootstrap(t, down, 200, 7).time_to(std::log(2.0), 0.9).known);
  EXPECT_FALSE(DriftRandomWalk(t, down).time_to(std::log(2.0), 0.9).known);
}

TEST(SimulatedRuns, InverseGaussianFirstPassage) {
  // Mean m, shape lambda: CDF(0) = 0, increasing, CDF(inf) = 1; the median of IG(1, 1) is 0.6758 (tables).
  EXPECT_EQ(inverse_gaussian_cdf(0.0, 1.0, 1.0), 0.0);
  EXPECT_NEAR(inverse_gaussian_cdf(0.675841, 1.0, 1.0), 0.5, 1e-5);
  EXPECT_NEAR(inverse_gaussian_cdf(1e6, 1.0, 1.0), 1.0, 1e-9);
  // A very sharp law (lambda / m = 1e4) still gives a finite CDF near its mean (no overflow of exp(2 lambda / m)).
  const double c = inverse_gaussian_cdf(1.0, 1.0, 1e4);
  EXPECT_TRUE(std::isfinite(c));
  EXPECT_NEAR(c, 0.5, 0.01);
  // The random walk's median on a noisy line with drift 0.05 / h: near gap / drift.
  std::vector<double> t, y;
  for (int i = 0; i <= 120; ++i) {
    t.push_back(i / 6.0);
    y.push_back(0.05 * t.back() + 0.002 * ((i * 7) % 5 - 2.0));
  }
  const Prediction rw = DriftRandomWalk(t, y).time_to(y.back() + 0.5, 0.9);
  ASSERT_TRUE(rw.known);
  EXPECT_NEAR(rw.hours, 0.5 / 0.05, 1.0);
  EXPECT_LT(rw.low, rw.hours);
  EXPECT_GT(rw.high, rw.hours);
}

// Conformal intervals on the channel's own level forecasts: on a straight line every past forecast at the mean
// rate was exact, so the interval collapses on the exact crossing; a horizon longer than the record, or a level
// that is not rising, is unknown.
TEST(SimulatedRuns, ConformalOnAStraightLine) {
  std::vector<double> t, y;
  for (int i = 0; i <= 240; ++i) {
    t.push_back(i / 6.0);          // 40 h at 10-min spacing
    y.push_back(0.05 * t.back());  // 0.05 per hour, no noise
  }
  const ConformalLevel line(t, y);
  const Prediction p = line.time_to(y.back() + 0.5, 0.9);
  ASSERT_TRUE(p.known) << p.why;
  EXPECT_NEAR(p.hours, 10.0, 1e-6);
  EXPECT_NEAR(p.low, 10.0, 1e-6);
  EXPECT_NEAR(p.high, 10.0, 1e-6);
  const Prediction far = line.time_to(y.back() + 2.0, 0.9);  // 40 h ahead: no past errors that far
  EXPECT_FALSE(far.known);
  EXPECT_NE(far.why.find("horizons on record"), std::string::npos) << far.why;
  EXPECT_TRUE(line.time_to(y.back() - 0.1, 0.9).reached);
  std::vector<double> down(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) down[i] = -y[i];
  EXPECT_FALSE(ConformalLevel(t, down).time_to(0.5, 0.9).known);
}

// Episodic wear (SimSpec::episodic): the same run with the level holding 4-24 h and catching up with the smooth
// path in 1 h. Its draws come from a separate stream: the rows before the onset are the smooth run's, bit for
// bit, and every noise-free crossing lies in a catch-up hour.
TEST(SimulatedRuns, EpisodicWearHoldsThenCatchesUp) {
  constexpr double kNsPerHour = 3.6e12;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SimSpec smooth_spec;
    smooth_spec.seed = seed;
    SimSpec episodic_spec = smooth_spec;
    episodic_spec.episodic = true;
    const SimRun smooth = simulate_run_to_failure(smooth_spec), episodic = simulate_run_to_failure(episodic_spec);
    ASSERT_TRUE(smooth.episode_ends_h.empty());
    ASSERT_GE(episodic.episode_ends_h.size(), 2u) << "seed " << seed;
    for (int row = 0; row < smooth_spec.healthy_rows; ++row) {
      ASSERT_EQ(smooth.features(row, 0), episodic.features(row, 0)) << "seed " << seed << " row " << row;
      ASSERT_EQ(smooth.time_ns[static_cast<std::size_t>(row)], episodic.time_ns[static_cast<std::size_t>(row)]);
    }
    EXPECT_GE(episodic.stop_ns, smooth.stop_ns) << "a hold only delays the wear";
    for (const double ratio : {2.0, 4.0, 6.0}) {
      const double tau = static_cast<double>(episodic.crossing_ns(ratio) - episodic.onset_ns) / kNsPerHour;
      EXPECT_GE(tau, static_cast<double>(smooth.crossing_ns(ratio) - smooth.onset_ns) / kNsPerHour - 1e-6);
      const bool in_catch_up = std::any_of(episodic.episode_ends_h.begin(), episodic.episode_ends_h.end(),
                                           [&](double end) { return tau >= end - 1.0 - 1e-6 && tau <= end + 1e-6; });
      EXPECT_TRUE(in_catch_up) << "seed " << seed << " ratio " << ratio << " at " << tau << " h";
      EXPECT_LE(episodic.crossing_ns(ratio), episodic.stop_ns + static_cast<std::int64_t>(kNsPerHour));
    }
  }
}
