// Intervals of what-if effects: quantile function, closed-form linear case, and coverage of the TRUE
// interventional effect when the model is estimated by the order-restricted Kalman filter.
#include "causal/analysis/uncertainty.hpp"

#include <gtest/gtest.h>

#include <causal/estimation/svar_kalman_filter.hpp>
#include <causal/estimation/svar_layout.hpp>

#include <cmath>
#include <cstdio>
#include <random>

#include "causal/analysis/var_lingam.hpp"
#include "matrix_asserts.hpp"
#include "svar_sim.hpp"
#include "two_channel_posterior.hpp"

using namespace causal;  // ModelSpec, NoiseParams, SvarKalmanFilter, SvarLayout
using namespace causal::analysis;
using namespace causal::analysis::test;

namespace {

TEST(Uncertainty, NormalQuantile) {
  EXPECT_NEAR(causal::estimation::normal_quantile(0.5), 0.0, 1e-15);
  EXPECT_NEAR(causal::estimation::normal_quantile(0.95), 1.6448536269514722, 1e-13);
  EXPECT_NEAR(causal::estimation::normal_quantile(0.975), 1.959963984540054, 1e-13);
  EXPECT_NEAR(causal::estimation::normal_quantile(0.025), -1.959963984540054, 1e-13);
  for (double p : {1e-12, 1e-6, 0.01, 0.02425, 0.3, 0.7, 0.99, 1.0 - 1e-9}) {
    const double x = causal::estimation::normal_quantile(p);
    EXPECT_NEAR(0.5 * std::erfc(-x / std::sqrt(2.0)), p, 1e-14 + 1e-12 * p) << p;
  }
  EXPECT_THROW(causal::estimation::normal_quantile(0.0), std::invalid_argument);
  EXPECT_THROW(causal::estimation::normal_quantile(1.0), std::invalid_argument);
}

// G = 2, one lag, y2 = b y1 + a y2[n-1] + e2 with only b uncertain: the steady-state effect of do(y1 + delta)
// on y2 is b delta / (1 - a), LINEAR in b, so its interval is exactly b delta/(1-a) +- z s delta/(1-a).
struct LinearCase : TwoChannelPosterior {
  double b = 0.6, a = 0.5, s = 0.05, delta = -0.2;
  LinearCase() : TwoChannelPosterior(0.6, 0.5, 0.05, 0.0) {}
};

TEST(Uncertainty, LinearCaseMatchesClosedFormBothMethods) {
  const LinearCase c;
  InterventionQuery q;
  q.channel = 0;
  q.delta = c.delta;
  const double z = 1.6448536269514722;  // 90%
  const double centre = c.b * c.delta / (1 - c.a);
  const double half = z * c.s * std::abs(c.delta) / (1 - c.a);

  UncertaintyOptions opt;
  opt.method = IntervalMethod::delta_method;
  const UncertainEffect d = predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt);
  ASSERT_TRUE(d.interval_valid);
  EXPECT_NEAR(d.point.steady_state(1), centre, 1e-15);
  EXPECT_NEAR(d.steady_state.lower(1), centre - half, 1e-9);
  EXPECT_NEAR(d.steady_state.upper(1), centre + half, 1e-9);
  EXPECT_NEAR(d.immediate.std_dev(1), c.s * std::abs(c.delta), 1e-9);

  opt.method = IntervalMethod::monte_carlo;
  opt.draws = 4000;
  const UncertainEffect mc = predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt);
  ASSERT_TRUE(mc.interval_valid);
  EXPECT_EQ(mc.draws_used, 4000);
  EXPECT_EQ(mc.draws_rejected, 0);
  EXPECT_DOUBLE_EQ(mc.coverage, 0.9);
  // Percentiles of 4000 normal draws: standard error of a 5% quantile ~ 0.03 sd; allow 0.1 sd.
  const double sd = c.s * std::abs(c.delta) / (1 - c.a);
  EXPECT_NEAR(mc.steady_state.lower(1), centre - half, 0.1 * sd);
  EXPECT_NEAR(mc.steady_state.upper(1), centre + half, 0.1 * sd);
  EXPECT_NEAR(mc.steady_state.std_dev(1), sd, 0.05 * sd);
  // The intervened channel carries no uncertainty.
  EXPECT_DOUBLE_EQ(mc.steady_state.lower(0), c.delta);
  EXPECT_DOUBLE_EQ(mc.steady_state.upper(0), c.delta);

  // Fixed seed: bit-identical rerun.
  const UncertainEffect again = predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt);
  EXPECT_EQ(again.steady_state.lower(1), mc.steady_state.lower(1));
}

TEST(Uncertainty, DrawsThatDoNotSettleAreCountedAndLeftOut) {
  LinearCase c;
  const int ia = c.layout.factor_index(1, 1, 1);
  c.posterior.mean(c.layout.offset(1) + ia) = 0.97;
  c.posterior.blocks[1](ia, ia) = 0.02 * 0.02;  // P(a >= 1) ~ 7%
  InterventionQuery q;
  q.channel = 0;
  q.delta = 1.0;
  UncertaintyOptions opt;
  opt.draws = 1000;
  const UncertainEffect mc = predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt);
  EXPECT_EQ(mc.point.status, AnalysisStatus::ok);
  EXPECT_GT(mc.draws_rejected, 20);
  EXPECT_LT(mc.draws_rejected, 150);
  EXPECT_EQ(mc.draws_used + mc.draws_rejected, 1000);
  EXPECT_TRUE(mc.interval_valid);

  // A point estimate that is unstable gives the status and no interval.
  c.posterior.mean(c.layout.offset(1) + ia) = 1.05;
  const UncertainEffect bad = predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt);
  EXPECT_EQ(bad.point.status, AnalysisStatus::unstable);
  EXPECT_FALSE(bad.interval_valid);
}

TEST(Uncertainty, BadOptionsThrow) {
  const LinearCase c;
  InterventionQuery q;
  UncertaintyOptions opt;
  opt.coverage = 1.0;
  EXPECT_THROW(predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt), std::invalid_argument);
  opt.coverage = 0.9;
  opt.draws = 1;
  EXPECT_THROW(predict_intervention_with_uncertainty(c.layout, c.posterior, q, opt), std::invalid_argument);
  FactorPosterior wrong = c.posterior;
  wrong.blocks.pop_back();
  EXPECT_THROW(predict_intervention_with_uncertainty(c.layout, wrong, q, {}), std::invalid_argument);
}

// The proof the brief asks for: simulate a structural VAR with known coefficients, estimate it (VAR-LiNGAM
// order on a calibration window, then the order-restricted Kalman filter), predict a sustained shift with a
// 90% interval, and check the interval against the effect in the TRUE system (mean over noise of
// intervened - baseline simulations). Counted over seeds and channels; intervals should cover ~90%.
TEST(Uncertainty, IntervalsCoverTrueInterventionalEffect) {
  const int g = 4;
  const int seeds = 20;
  int covered_ss = 0, covered_now = 0, total = 0;
  int covered_ss_delta = 0;
  for (int s = 0; s < seeds; ++s) {
    std::mt19937_64 rng(9000 + static_cast<std::uint64_t>(s));
    const TrueSvar truth = random_svar(rng, g, 1);
    const int n = 3000;
    const Eigen::MatrixXd e = draw_noise(rng, n + 200, Eigen::VectorXd::Ones(g), NoiseKind::laplace);
    const Eigen::MatrixXd y = simulate(truth, e).bottomRows(n);

    causal::estimation::ModelSpec spec;
    spec.channels = g;
    spec.lag_order = 1;
    spec.include_self_lags = true;
    const VarLingamResult lingam = var_lingam(y.topRows(1000));
    const causal::estimation::SvarLayout layout(lingam.restrict(spec));
    std::vector<causal::estimation::NoiseParams> noise;
    for (int k = 0; k < g; ++k) noise.push_back(causal::estimation::NoiseParams{1e-9, lingam.noise_variance(k), 1.0});
    causal::estimation::SvarKalmanFilter filter(layout, noise);
    for (int t = 0; t < n; ++t) {
      const Eigen::VectorXd row = y.row(t).transpose();  // contiguous copy: y is column-major
      filter.step(row.data());
    }
    const FactorPosterior posterior = posterior_from_filter(layout, filter);

    // Intervene on the second channel of the true order: it has both ancestors and descendants.
    const int j = truth.order[1];
    InterventionQuery q;
    q.channel = j;
    q.delta = 1.0;
    UncertaintyOptions opt;
    opt.draws = 1000;
    const UncertainEffect mc = predict_intervention_with_uncertainty(layout, posterior, q, opt);
    ASSERT_EQ(mc.point.status, AnalysisStatus::ok) << mc.point.message;
    ASSERT_TRUE(mc.interval_valid);
    opt.method = IntervalMethod::delta_method;
    const UncertainEffect dm = predict_intervention_with_uncertainty(layout, posterior, q, opt);
    ASSERT_TRUE(dm.interval_valid);

    // True effect: average over 5 noise realisations of the simulated change (same noise both arms).
    Eigen::VectorXd true_now = Eigen::VectorXd::Zero(g), true_ss = Eigen::VectorXd::Zero(g);
    for (int r = 0; r < 5; ++r) {
      const int len = 400, n0 = 50;
      const Eigen::MatrixXd er = draw_noise(rng, n0 + len, Eigen::VectorXd::Ones(g), NoiseKind::laplace);
      const Eigen::MatrixXd base = simulate(truth, er);
      Eigen::MatrixXd forced = no_force(n0 + len, g);
      for (int t = n0; t < n0 + len; ++t) forced(t, j) = base(t, j) + q.delta;
      const Eigen::MatrixXd d = simulate(truth, er, &forced) - base;
      true_now += d.row(n0).transpose() / 5.0;
      true_ss += d.row(n0 + len - 1).transpose() / 5.0;
    }
    for (int k = 0; k < g; ++k) {
      if (k == j) continue;
      ++total;
      covered_now += mc.immediate.lower(k) <= true_now(k) && true_now(k) <= mc.immediate.upper(k);
      covered_ss += mc.steady_state.lower(k) <= true_ss(k) && true_ss(k) <= mc.steady_state.upper(k);
      covered_ss_delta += dm.steady_state.lower(k) <= true_ss(k) && true_ss(k) <= dm.steady_state.upper(k);
    }
  }
  const double cov_now = static_cast<double>(covered_now) / total;
  const double cov_ss = static_cast<double>(covered_ss) / total;
  const double cov_dm = static_cast<double>(covered_ss_delta) / total;
  std::printf("[ Uncertainty ] 90%% intervals covering the true effect (%d seed x channel pairs): immediate %.1f%%, "
              "steady state %.1f%% (Monte Carlo), steady state %.1f%% (delta method)\n",
              total, 100.0 * cov_now, 100.0 * cov_ss, 100.0 * cov_dm);
  // 60 pairs of a nominal 90% interval: binomial sd ~ 3.9 points; 75% is > 3.5 sd below nominal.
  EXPECT_GE(cov_now, 0.75);
  EXPECT_GE(cov_ss, 0.75);
  EXPECT_GE(cov_dm, 0.75);
}

}  // namespace
