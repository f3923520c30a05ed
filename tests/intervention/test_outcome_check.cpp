// The outcome check (O1)-(O3) on a simulated AR(1) target whose true intervention effect is known: the check
// interval covers the truth about as often as promised, an effect that did not happen is caught, and what
// cannot be checked says why.
#include "causal/intervention/outcome_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace causal::intervention;

namespace {

// z[n] = 0.3 z[n-1] + e, e uniform sd 0.02; from `start` for `duration` snapshots the true effect `effect` is
// added (a step). Returns the finished outcomes.
std::vector<Outcome> run_one(std::uint64_t seed, double effect, const Prediction& prediction, OutcomeCheck& check,
                             const std::string& group = "g", std::uint64_t start = 100, std::uint64_t duration = 24) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.035, 0.035);
  InterventionPlan plan{group + "/r@" + std::to_string(start), group, "alarm/1", 1, 0, std::log(0.6), start, duration};
  check.approve(plan);
  std::vector<Outcome> done;
  double z = 0.0;
  for (std::uint64_t n = 0; n < start + duration + 5; ++n) {
    z = 0.3 * z + u(rng);
    const double applied = n >= start && n < start + duration ? effect : 0.0;
    Eigen::VectorXd levels(2);
    levels << std::log(0.08) + z + applied, 0.0;
    check.observe(group, n, levels, done);
    for (const auto& p : check.due(group, n)) check.freeze(p.request_id, prediction, done);
  }
  return done;
}

Prediction steady(double effect, double half_width) {
  Prediction p;
  p.ok = true;
  p.steady_state = true;
  p.effect = effect;
  p.low = effect - half_width;
  p.high = effect + half_width;
  return p;
}

}  // namespace

TEST(OutcomeCheck, ExactPredictionIsInsideAboutAsOftenAsPromised) {
  int inside = 0, improved = 0;
  const int runs = 200;
  for (int s = 0; s < runs; ++s) {
    OutcomeCheck check;
    const auto done = run_one(1000 + s, -0.5, steady(-0.5, 0.0), check);  // a point prediction: only (O3) widens it
    ASSERT_EQ(done.size(), 1u);
    ASSERT_EQ(done[0].status, "checked") << done[0].why;
    inside += done[0].inside;
    improved += done[0].improved;
    EXPECT_EQ(done[0].compare_to, 123u);
    EXPECT_EQ(done[0].compare_from, 118u);
  }
  // 90 % promised: 200 runs give 180 +- 8.5 (binomial sd 4.2); the forecast's error model is approximate.
  EXPECT_GE(inside, 168) << inside << " of " << runs;
  EXPECT_LE(inside, 199) << inside << " of " << runs;
  EXPECT_EQ(improved, runs);
}

TEST(OutcomeCheck, AnEffectThatDidNotHappenIsAMissAndCostsTheLeverItsClaim) {
  OutcomeCheck check;
  const auto first = run_one(7, 0.0, steady(-0.5, 0.1), check, "g", 100);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_FALSE(first[0].inside);
  EXPECT_NEAR(first[0].observed, 0.0, 0.05);
  EXPECT_TRUE(first[0].lever_claimed);  // one miss: 2/4
  OutcomeCheck again;
  run_one(7, 0.0, steady(-0.5, 0.1), again, "g", 100);
  const auto second = run_one(8, 0.0, steady(-0.5, 0.1), again, "g", 200);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_FALSE(second[0].inside);
  EXPECT_FALSE(second[0].lever_claimed);
  EXPECT_NEAR(second[0].lever_trust, 0.4, 1e-12);
}

TEST(OutcomeCheck, HorizonAnswersAreComparedAtTheirHorizon) {
  OutcomeCheck check;
  Prediction p = steady(-0.5, 0.05);
  p.steady_state = false;
  p.horizon = 12;
  const auto done = run_one(3, -0.5, p, check);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].compare_from, 112u);
  EXPECT_EQ(done[0].compare_to, 112u);
  EXPECT_TRUE(done[0].inside) << done[0].observed;
  p.horizon = 30;  // past the 24-snapshot window
  OutcomeCheck short_window;
  const auto refused = run_one(3, -0.5, p, short_window);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].status, "no_forecast");
}

TEST(OutcomeCheck, WhatCannotBeCheckedSaysWhy) {
  OutcomeCheck check;
  Prediction none;
  none.why = "the system does not settle";
  const auto done = run_one(1, -0.5, none, check);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].status, "no_forecast");
  EXPECT_NE(done[0].why.find("does not settle"), std::string::npos);
  OutcomeCheck young;
  const auto early = run_one(1, -0.5, steady(-0.5, 0.1), young, "g", 5);
  ASSERT_EQ(early.size(), 1u);
  EXPECT_EQ(early[0].status, "no_forecast");
  EXPECT_EQ(young.pending(), 0u);
  // The same approval twice is one intervention.
  InterventionPlan plan{"x", "g", "", 1, 0, -0.1, 10, 5};
  EXPECT_TRUE(check.approve(plan));
  EXPECT_FALSE(check.approve(plan));
}

TEST(OutcomeCheck, SameDataSameOutcome) {
  OutcomeCheck a, b;
  const auto x = run_one(42, -0.3, steady(-0.3, 0.05), a);
  const auto y = run_one(42, -0.3, steady(-0.3, 0.05), b);
  ASSERT_EQ(x.size(), 1u);
  ASSERT_EQ(y.size(), 1u);
  EXPECT_EQ(x[0].observed, y[0].observed);
  EXPECT_EQ(x[0].check_low, y[0].check_low);
  EXPECT_EQ(x[0].check_high, y[0].check_high);
}
