// The prognosis as alarm-recommender runs it (alarm engine + channel trends) on simulated run-to-failure
// channels with known crossing times (causal-prognosis-eval's simulator): the healthy channel gets no
// prognosis, the wearing one does, and its median error is well below the Theil-Sen baseline's.
#include "prognosis_scoring.hpp"
#include "run_to_failure_sim.hpp"

#include <gtest/gtest.h>

#include <algorithm>

using namespace causal;
using namespace causal::prognosis_eval;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[v.size() / 2];
}

}  // namespace

TEST(SimulatedRuns, TwinBeatsTheilSenAndCoversOften) {
  MethodScores twin, base;
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
    for (int l = 0; l < kLevels; ++l) {
      twin.level[static_cast<std::size_t>(l)].merge(s.twin().level[static_cast<std::size_t>(l)]);
      base.level[static_cast<std::size_t>(l)].merge(s.baseline().level[static_cast<std::size_t>(l)]);
    }
  }
  for (int l = 0; l < kLevels; ++l) {
    const auto& t = twin.level[static_cast<std::size_t>(l)];
    const auto& b = base.level[static_cast<std::size_t>(l)];
    ASSERT_GT(t.decisions, 100u);
    ASSERT_GT(t.known, 10u) << "level " << l;
    EXPECT_LT(median(t.abs_errors), 0.5 * median(b.abs_errors)) << "level " << l;
    EXPECT_GT(static_cast<double>(t.covered) / static_cast<double>(t.known),
              static_cast<double>(b.covered) / std::max<double>(1.0, static_cast<double>(b.known)))
        << "level " << l;
  }
}
