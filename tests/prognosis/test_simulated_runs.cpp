// The prognosis as alarm-recommender runs it (alarm engine + channel trends) on simulated run-to-failure
// channels with known crossing times (causal-prognosis-eval's simulator): the healthy channel gets no
// prognosis, the wearing one does, and it is ahead of both anchors (Theil-Sen with bootstrap intervals,
// random walk with drift) in coverage and point accuracy.
#include "prognosis_scoring.hpp"
#include "run_to_failure_sim.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

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
  for (int l = 0; l < kLevels; ++l) {
    const auto& t = all[0].level[static_cast<std::size_t>(l)];
    ASSERT_GT(t.decisions, 100u);
    ASSERT_GT(t.known, 10u) << "level " << l;
    for (int m = 1; m < kMethods; ++m) {
      const auto& a = all[static_cast<std::size_t>(m)].level[static_cast<std::size_t>(l)];
      ASSERT_EQ(a.decisions, t.decisions) << "the anchors are scored at the same decision points";
      EXPECT_GT(coverage(t), coverage(a)) << method_name(m) << " level " << l;
      EXPECT_GT(t.within_30, a.within_30) << method_name(m) << " level " << l;
    }
  }
}
