// causal::advice::Advisor (common/advice/src/advisor.cpp): what-if and recommendation intervals
// from the FULL per-outcome factor covariance P_k when every outcome carries one, diagonal blocks from the
// standard deviations otherwise.
//
// Independent truth: in the model below (channel 2's equation holds only channel 1: a configured graph) the
// steady-state effect of a sustained shift of channel 1 on channel 2 is LINEAR in the factors,
// d_2 = (x21 + xL21) delta (W3), so it is exactly normal and its
// central interval is a closed form: point -/+ z sd with sd = |delta| sqrt(Var x21 + Var xL21 + 2 Cov).
// Channel 3's effect is non-linear (products of factors): checked against a Monte Carlo written here (own
// sampler, own dense (W3) solve).
#include "causal/advice/advisor.hpp"

#include "causal/analysis/bounded_answer.hpp"
#include "causal/analysis/recommendation.hpp"
#include "causal/analysis/uncertainty.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace causal::advice {
namespace {

constexpr double kSigma = 0.05;  // sd of every factor
constexpr double kRho = -0.9;    // correlation of x_kj with xL_kj (instantaneous vs lag-1, same j)
constexpr double kCoverage = 0.9;
constexpr double kZ = 1.6448536269514722;  // Phi^{-1}(0.95)

// Outcomes 1 and 3: x_ka x_kb xL_ka xL_kb (a < b, both != k); outcome 2: x21 xL21 only (3 -> 2 masked, so
// channel 2 cannot be fed back by channel 3 and its effect stays linear in the factors).
estimation::SvarLayout make_layout() {
  estimation::ModelSpec s;
  s.channels = 3;
  s.lag_order = 1;
  s.include_self_lags = false;
  s.allowed.assign(3, std::vector<bool>(3, true));
  s.allowed[1][2] = false;
  return estimation::SvarLayout(s);
}

// Acyclic chain 1 -> 2 -> 3 plus 1 -> 3; every other factor 0.
Eigen::VectorXd mean_factors(const estimation::SvarLayout& l) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(l.total_factors());
  const auto set = [&](const std::string& name, double v) {
    const auto& names = l.factor_names();
    const auto it = std::find(names.begin(), names.end(), name);
    ASSERT_NE(it, names.end()) << name;
    x[it - names.begin()] = v;
  };
  set("x21", 0.5);
  set("xL21", 0.2);
  set("x31", 0.2);
  set("xL31", 0.1);
  set("x32", 0.4);
  set("xL32", 0.1);
  return x;
}

// d = 2h factors (h instantaneous, then h lag 1, same channels): sd kSigma, correlation kRho between factor i
// (instantaneous on j) and i + h (lag 1 on j).
Eigen::MatrixXd correlated_block(int d) {
  const int h = d / 2;
  Eigen::MatrixXd p = kSigma * kSigma * Eigen::MatrixXd::Identity(d, d);
  for (int i = 0; i < h; ++i) p(i, i + h) = p(i + h, i) = kRho * kSigma * kSigma;
  return p;
}

std::vector<Eigen::MatrixXd> correlated_blocks(const estimation::SvarLayout& l) {
  std::vector<Eigen::MatrixXd> out;
  for (int k = 0; k < l.channels(); ++k) out.push_back(correlated_block(l.factor_count(k)));
  return out;
}

std::vector<Eigen::MatrixXd> diagonal_blocks(const estimation::SvarLayout& l) {
  std::vector<Eigen::MatrixXd> out;
  for (const auto& b : correlated_blocks(l)) out.push_back(b.diagonal().asDiagonal());
  return out;
}

ModelObservation observation(const estimation::SvarLayout& l, bool with_blocks) {
  ModelObservation a;
  a.asset_group = "ims2";
  a.channel_names = {"b1", "b2", "b3"};
  a.factor_names = l.factor_names();
  a.lag_order = 1;
  a.observation.index = 5;
  a.observation.factors = mean_factors(l);
  a.observation.factor_std = Eigen::VectorXd::Constant(l.total_factors(), kSigma);
  // RMS now: channel 1 is 10 % (in log level) above its baseline, 2 and 3 at baseline (see baseline()).
  a.observation.features = Eigen::Vector3d(0.2, 0.1, 0.1);
  if (with_blocks) a.covariance_blocks = correlated_blocks(l);
  return a;
}

Eigen::VectorXd baseline() { return Eigen::Vector3d(0.2 * std::exp(-0.1), 0.1, 0.1); }

AdvisorParams params() {
  AdvisorParams p;
  p.coverage = kCoverage;
  p.draws = 4000;
  p.model_log_features = true;
  return p;
}

// Closed-form interval of channel 2's steady-state change under do(y_1 += delta).
struct Interval {
  double lower, upper;
};
Interval closed_form_channel2(double delta, double rho) {
  const double point = (0.5 + 0.2) * delta;
  const double sd = std::abs(delta) * kSigma * std::sqrt(2.0 + 2.0 * rho);
  return {point - kZ * sd, point + kZ * sd};
}

// Own Monte Carlo of the steady-state change of every channel, (W3): d = (I - A0c - A1c)^{-1} e_1 delta with
// row 0 (channel 1's equation) cut. Returns the (1-c)/2 and (1+c)/2 sample quantiles of channel 3.
Interval monte_carlo_channel3(const estimation::SvarLayout& l, const std::vector<Eigen::MatrixXd>& blocks, double delta,
                              int draws) {
  const Eigen::VectorXd mean = mean_factors(l);
  std::vector<Eigen::MatrixXd> roots;
  for (const auto& b : blocks) roots.push_back(b.llt().matrixL());
  std::mt19937_64 rng(777);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> d3;
  for (int n = 0; n < draws; ++n) {
    Eigen::VectorXd x = mean;
    for (int k = 0; k < 3; ++k) {
      const int d = l.factor_count(k);
      Eigen::VectorXd z(d);
      for (int i = 0; i < d; ++i) z[i] = normal(rng);
      x.segment(l.offset(k), d) += roots[static_cast<std::size_t>(k)] * z;
    }
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();  // A0 + A1, rows k, columns j
    for (int k = 1; k < 3; ++k) {                 // row 0 cut by the intervention
      const auto& regs = l.regressors(k);
      for (int i = 0; i < l.factor_count(k); ++i) a(k, regs[static_cast<std::size_t>(i)].channel) += x[l.offset(k) + i];
    }
    const Eigen::Vector3d rhs(delta, 0.0, 0.0);
    d3.push_back((Eigen::Matrix3d::Identity() - a).partialPivLu().solve(rhs)[2]);
  }
  std::sort(d3.begin(), d3.end());
  const auto at = [&](double p) { return d3[static_cast<std::size_t>(p * static_cast<double>(d3.size() - 1))]; };
  return {at(0.5 * (1 - kCoverage)), at(0.5 * (1 + kCoverage))};
}

TEST(Advisor, WhatIfUsesTheFullCovarianceBlocks) {
  const estimation::SvarLayout l = make_layout();
  Advisor full(params()), diag(params());
  full.update(observation(l, true));
  diag.update(observation(l, false));
  EXPECT_TRUE(full.full_covariance("ims2"));
  EXPECT_FALSE(diag.full_covariance("ims2"));

  const double delta = -0.1;
  const auto a = full.what_if("ims2", 0, delta, true);
  const auto b = diag.what_if("ims2", 0, delta, true);
  ASSERT_TRUE(a.ok) << a.error;
  ASSERT_TRUE(b.ok) << b.error;
  // The point is the median of the draws (linear in the factors here: the closed form up to Monte Carlo error).
  EXPECT_EQ(a.diag.kind, "steady_state");
  EXPECT_NEAR(a.steady_state[1], 0.7 * delta, 0.1 * std::abs(delta) * kSigma);
  EXPECT_NEAR(b.steady_state[1], 0.7 * delta, 0.1 * std::abs(delta) * kSigma * std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(a.steady_state[0], delta);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(a.lower[k], a.effect[k]);
    EXPECT_GE(a.upper[k], a.effect[k]);
  }
  // Percent of the current level (log-level model): 100 (e^d - 1), the intervened channel exactly -9.5 %.
  EXPECT_NEAR(a.percent[0], 100.0 * std::expm1(delta), 1e-12);
  EXPECT_NE(a.text.find("at steady state, 90 % intervals, model stable rho="), std::string::npos) << a.text;

  // Channel 2 against the closed forms: full (rho = -0.9) and diagonal (rho = 0). Tolerance: Monte Carlo error
  // of a 5 % quantile with 4000 draws is about 0.035 sd; allow 0.15 sd.
  const Interval want_full = closed_form_channel2(delta, kRho), want_diag = closed_form_channel2(delta, 0.0);
  const double sd_full = std::abs(delta) * kSigma * std::sqrt(2.0 + 2.0 * kRho);
  const double sd_diag = std::abs(delta) * kSigma * std::sqrt(2.0);
  EXPECT_NEAR(a.lower[1], want_full.lower, 0.15 * sd_full);
  EXPECT_NEAR(a.upper[1], want_full.upper, 0.15 * sd_full);
  EXPECT_NEAR(b.lower[1], want_diag.lower, 0.15 * sd_diag);
  EXPECT_NEAR(b.upper[1], want_diag.upper, 0.15 * sd_diag);
  // And the two differ by far more than Monte Carlo noise: the full interval is ~3x narrower.
  const double width_full = a.upper[1] - a.lower[1], width_diag = b.upper[1] - b.lower[1];
  EXPECT_LT(width_full, 0.5 * width_diag) << width_full << " vs " << width_diag;

  // Channel 3 (non-linear in the factors) against this test's own Monte Carlo with the full blocks.
  const Interval mc3 = monte_carlo_channel3(l, correlated_blocks(l), delta, 40000);
  const double width3 = mc3.upper - mc3.lower;
  EXPECT_NEAR(a.lower[2], mc3.lower, 0.1 * width3);
  EXPECT_NEAR(a.upper[2], mc3.upper, 0.1 * width3);
  const Interval mc3_diag = monte_carlo_channel3(l, diagonal_blocks(l), delta, 40000);
  EXPECT_GT(std::abs((b.upper[2] - b.lower[2]) - width3), 0.3 * width3) << "diagonal fallback must differ";
  EXPECT_NEAR(b.upper[2] - b.lower[2], mc3_diag.upper - mc3_diag.lower, 0.1 * (mc3_diag.upper - mc3_diag.lower));

  // Same options, same posterior: identical to the analysis library called directly.
  causal::analysis::InterventionQuery q;
  q.channel = 0;
  q.delta = delta;
  q.kind = causal::analysis::InterventionKind::sustained;
  causal::analysis::UncertaintyOptions u;
  u.coverage = kCoverage;
  u.draws = params().draws;
  const causal::analysis::FactorPosterior posterior{mean_factors(l), correlated_blocks(l)};
  const auto ref = causal::analysis::answer_intervention(l, posterior, q, params().rule, u);
  ASSERT_TRUE(ref.answered());
  EXPECT_TRUE((a.lower.array() == ref.effect.lower.array()).all());
  EXPECT_TRUE((a.upper.array() == ref.effect.upper.array()).all());
  EXPECT_TRUE((a.effect.array() == ref.effect.median.array()).all());
}

TEST(Advisor, RecommendationIntervalUsesTheFullCovarianceBlocks) {
  const estimation::SvarLayout l = make_layout();
  Advisor full(params()), diag(params());
  full.update(observation(l, true));
  diag.update(observation(l, false));
  std::string why_full, why_diag;
  const auto a = full.advise("ims2", 1, baseline(), why_full);
  const auto b = diag.advise("ims2", 1, baseline(), why_diag);
  ASSERT_EQ(a.size(), 1u) << why_full;
  ASSERT_EQ(b.size(), 1u) << why_diag;
  EXPECT_EQ(a[0].intervene, 0);
  EXPECT_NEAR(a[0].delta, -0.1, 1e-12);
  const Interval want_full = closed_form_channel2(a[0].delta, kRho), want_diag = closed_form_channel2(b[0].delta, 0.0);
  const double sd_full = 0.1 * kSigma * std::sqrt(2.0 + 2.0 * kRho), sd_diag = 0.1 * kSigma * std::sqrt(2.0);
  EXPECT_NEAR(a[0].lower, want_full.lower, 0.15 * sd_full);
  EXPECT_NEAR(a[0].upper, want_full.upper, 0.15 * sd_full);
  EXPECT_NEAR(b[0].lower, want_diag.lower, 0.15 * sd_diag);
  EXPECT_NEAR(b[0].upper, want_diag.upper, 0.15 * sd_diag);
  EXPECT_LT(a[0].upper - a[0].lower, 0.5 * (b[0].upper - b[0].lower));
  // Same draws for point and interval; "reliable" means the interval excludes no reduction; one line in the text.
  for (const auto* item : {&a[0], &b[0]}) {
    EXPECT_LE(item->lower, item->effect);
    EXPECT_GE(item->upper, item->effect);
    EXPECT_LE(item->percent_lower, item->percent);
    EXPECT_GE(item->percent_upper, item->percent);
    EXPECT_GE(item->percent_lower, -100.0);
    EXPECT_EQ(item->reliable, item->upper < 0.0);
    EXPECT_EQ(item->diag.kind, "steady_state");
    EXPECT_NE(item->summary.find("at steady state: "), std::string::npos) << item->summary;
    EXPECT_NE(item->summary.find(" (90 %), model stable rho="), std::string::npos) << item->summary;
    EXPECT_NE(item->text.find(item->summary), std::string::npos) << item->text;
    EXPECT_EQ(item->text.rfind(item->reliable ? "Reduce b1 by 9.5 %" : "No reliable lever for b2", 0), 0u) << item->text;
  }
}

TEST(Advisor, ARawLevelCannotBeReducedByMoreThanItsLevel) {
  const estimation::SvarLayout l = make_layout();
  AdvisorParams p = params();
  p.model_log_features = false;
  Advisor adv(p);
  adv.update(observation(l, true));  // channel 1's level is 0.2
  const auto bad = adv.what_if("ims2", 0, -0.5, true);
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("impossible intervention on b1"), std::string::npos) << bad.error;
  EXPECT_NE(bad.error.find("below zero"), std::string::npos) << bad.error;
  const auto good = adv.what_if("ims2", 0, -0.1, true);
  ASSERT_TRUE(good.ok) << good.error;
  EXPECT_NEAR(good.percent[0], -50.0, 1e-12);  // -0.1 of a level 0.2
}

TEST(Advisor, AChannelWithinItsNormalSpreadIsNoCandidate) {
  // Channel 1 is exp(0.1) - 1 = 10.5 % above its baseline: a candidate at a 10 % minimum, none at 11 %.
  const estimation::SvarLayout l = make_layout();
  for (const double min_percent : {10.0, 11.0}) {
    AdvisorParams p = params();
    p.min_excess_percent = min_percent;
    Advisor adv(p);
    adv.update(observation(l, true));
    std::string why;
    const auto advice = adv.advise("ims2", 1, baseline(), why);
    if (min_percent == 10.0) {
      ASSERT_EQ(advice.size(), 1u) << why;
      EXPECT_EQ(advice[0].intervene, 0);
    } else {
      EXPECT_TRUE(advice.empty());
      EXPECT_NE(why.find("11 % or more above its baseline"), std::string::npos) << why;
    }
  }
}

TEST(Advisor, FallsBackToDiagonalWhenBlocksAreMissingOrUnusable) {
  const estimation::SvarLayout l = make_layout();
  Advisor diag(params());
  diag.update(observation(l, false));
  const auto want = diag.what_if("ims2", 0, -0.1, true);
  ASSERT_TRUE(want.ok);

  // Blocks of the wrong size for the layout, or with a NaN: diagonal fallback, same answer as without blocks.
  ModelObservation wrong = observation(l, true);
  wrong.covariance_blocks[0] = Eigen::MatrixXd::Identity(3, 3);
  ModelObservation nan = observation(l, true);
  nan.covariance_blocks[2](0, 0) = std::nan("");
  for (const auto* obs : {&wrong, &nan}) {
    Advisor adv(params());
    adv.update(*obs);
    EXPECT_FALSE(adv.full_covariance("ims2"));
    const auto got = adv.what_if("ims2", 0, -0.1, true);
    ASSERT_TRUE(got.ok) << got.error;
    EXPECT_TRUE((got.lower.array() == want.lower.array()).all());
    EXPECT_TRUE((got.upper.array() == want.upper.array()).all());
  }

  // The latest observation decides: blocks, then none -> diagonal; then blocks again -> full.
  Advisor adv(params());
  adv.update(observation(l, true));
  EXPECT_TRUE(adv.full_covariance("ims2"));
  adv.update(observation(l, false));
  EXPECT_FALSE(adv.full_covariance("ims2"));
  adv.update(observation(l, true));
  EXPECT_TRUE(adv.full_covariance("ims2"));
  EXPECT_FALSE(adv.full_covariance("unknown"));
}

}  // namespace

namespace {

// The b1 -> b2 link (x21, xL21) set to zero: the model of a plant where b1 does not drive b2.
ModelObservation observation_without_link(const estimation::SvarLayout& l) {
  ModelObservation a = observation(l, true);
  const auto& names = l.factor_names();
  for (const char* f : {"x21", "xL21"}) {
    a.observation.factors[std::find(names.begin(), names.end(), f) - names.begin()] = 0.0;
  }
  return a;
}

std::string reference_of_b1_lever(const Advisor& adv) {
  std::string why;
  for (const auto& c : adv.evaluate("ims2", 1, baseline(), why)) {
    if (c.intervene == 0) return c.reference;
  }
  return "no candidate: " + why;
}

}  // namespace

TEST(Advisor, ALinkAbsentFromTheHealthyReferenceIsMarkedAppeared) {
  // Healthy models without the b1 -> b2 link, then models with it (x21 + xL21 = 0.7); 3 observations confirm a
  // candidate reference. No reference while learning or before a confirmation ("none"); a confirmed linkless
  // one makes the lever "appeared"; a confirmed one with the link "held"; while a degradation alarm is open
  // no candidate is captured or confirmed.
  const estimation::SvarLayout l = make_layout();
  AdvisorParams p = params();
  p.reference_confirm_observations = 3;
  for (const bool degraded : {false, true}) {
    Advisor adv(p);
    adv.update(observation_without_link(l));  // 1: learning (no set_health yet): nothing captured
    EXPECT_EQ(reference_of_b1_lever(adv), "none");
    adv.set_health("ims2", false, false);
    adv.update(observation_without_link(l));  // 2: candidate without the link
    for (int n = 3; n <= 4; ++n) adv.update(observation(l, true));
    EXPECT_EQ(reference_of_b1_lever(adv), "none");  // not confirmed yet
    adv.update(observation(l, true));  // 5: candidate 2 confirmed (no link); candidate 5 (link) captured
    EXPECT_EQ(reference_of_b1_lever(adv), "appeared");
    adv.set_health("ims2", false, degraded);
    for (int n = 6; n <= 8; ++n) adv.update(observation(l, true));  // 8: candidate 5 confirmed unless degraded
    EXPECT_EQ(reference_of_b1_lever(adv), degraded ? "appeared" : "held") << (degraded ? "degraded" : "healthy");
  }
}

}  // namespace causal::advice

namespace causal::advice {
namespace {

// Only the max_candidates levers with the largest excess over their baseline are evaluated (each costs `draws`
// solves of the whole model): b2 is 20 % (log) above its baseline, b1 10 %; the alarm is on b3.
TEST(Advisor, OnlyTheLargestExcessesAreEvaluated) {
  const estimation::SvarLayout l = make_layout();
  ModelObservation o = observation(l, true);
  o.observation.features = Eigen::Vector3d(0.2, 0.1 * std::exp(0.2), 0.1);
  for (const int max_candidates : {1, 2}) {
    AdvisorParams p = params();
    p.max_candidates = max_candidates;
    Advisor adv(p);
    adv.update(o);
    std::string why;
    const auto all = adv.evaluate("ims2", 2, baseline(), why);
    ASSERT_EQ(all.size(), static_cast<std::size_t>(max_candidates)) << why;
    std::vector<int> levers;
    for (const auto& a : all) levers.push_back(a.intervene);
    std::sort(levers.begin(), levers.end());
    const std::vector<int> expected = max_candidates == 1 ? std::vector<int>{1} : std::vector<int>{0, 1};
    EXPECT_EQ(levers, expected);
  }
}

}  // namespace
}  // namespace causal::advice
