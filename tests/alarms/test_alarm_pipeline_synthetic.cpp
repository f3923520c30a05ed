// The whole condition-level chain of the services (causal-estimator's condition pipeline with the shipped
// estimator.yaml, the instantaneous graph configured: centred log features, Kalman filter -> AlarmEngine) on synthetic data with a known answer: channel 2's own noise steps up at t = 400 and channel
// 3 follows through the causal link y3 = 0.8 y2 + n3. The filter's innovations must let the engine tell the
// root (2: its level is not explained by the others) from the follower (3: explained by 2).
#include <gtest/gtest.h>

#include "causal/alarms/alarm_pipeline.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;

namespace {

ConditionSeries to_series(const std::vector<Observation>& obs) {
  ConditionSeries s;
  s.channel_names = test::channel_names4();
  s.feature = "synthetic";
  s.values.resize(static_cast<Eigen::Index>(obs.size()), 4);
  for (std::size_t t = 0; t < obs.size(); ++t) {
    s.values.row(static_cast<Eigen::Index>(t)) = obs[t].features.transpose();
    s.time_ns.push_back(obs[t].time_ns);
    s.index.push_back(obs[t].index);
    s.discontinuity.push_back(t == 0);
  }
  return s;
}

}  // namespace

TEST(AlarmPipelineSynthetic, KalmanInnovationsSeparateRootFromFollower) {
  int seeds_with_own_change_alarm = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    test::SyntheticConfig cfg;
    cfg.seed = seed;
    cfg.own_change = [](int t) { return t >= 400 ? 6.0 : 0.0; };
    PipelineOptions opt = shipped_options("grp");
    // The synthetic noise is Gaussian: VAR-LiNGAM cannot order Gaussian channels (README, known limits),
    // so the structure is configured as estimator.yaml allows (instantaneous_graph, causal_order configured):
    // the true link 2 -> 3, everything else lagged only.
    opt.estimator.condition_structure.learn_order = false;
    opt.estimator.condition_graph = "2 -> 3";
    const auto res = run_condition_pipeline(to_series(test::make_run(cfg)), opt);
    ASSERT_TRUE(res.summary[1].alarmed) << "seed " << seed;
    ASSERT_TRUE(res.summary[2].alarmed) << "seed " << seed;
    EXPECT_GE(res.summary[1].first.index, 400u);
    // +12 % step: the size floor (+8 %, median of 5) must hold for level_window observations; when
    // noise makes the first values look like a +15 % operating step, the confirmation window comes first.
    const AlarmParams p;
    EXPECT_LE(res.summary[1].first.index,
              400u + static_cast<std::uint64_t>(p.confirmation_observations + 2 * p.level_window));
    bool innovation_on_2 = false;
    for (const auto& e : res.events) {
      EXPECT_GE(e.index, 400u) << "seed " << seed << ": " << e.reason;
      EXPECT_EQ(e.root_cause_channel, 1) << "seed " << seed << ": " << e.reason;
      EXPECT_FALSE(e.kind == kind::kInnovationRise && e.channel == 2) << "seed " << seed << ": follower flagged as own change";
      innovation_on_2 = innovation_on_2 || (e.kind == kind::kInnovationRise && e.channel == 1);
    }
    seeds_with_own_change_alarm += innovation_on_2 ? 1 : 0;
  }
  // The innovation_rise ALARM needs the root's innovations to stay high for ~2 observations; when the
  // maximum-likelihood q of the root's equation comes out large (it does on some 120-sample baselines),
  // the filter re-explains the new level within a few observations and only the departure-time evidence
  // remains -- which the root-cause tie-break uses (checked above for every seed).
  EXPECT_GE(seeds_with_own_change_alarm, 7);
  RecordProperty("seeds_with_own_change_alarm", seeds_with_own_change_alarm);
}
