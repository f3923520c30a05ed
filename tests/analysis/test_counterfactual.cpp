// Counterfactuals: exact reproduction without intervention, and agreement with re-simulating the TRUE system
// with the same noise and the held channel forced.
#include "causal/analysis/counterfactual.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "matrix_asserts.hpp"
#include "true_model.hpp"

using namespace causal::analysis;
using namespace causal::analysis::test;

namespace {

struct Fixture {
  TrueSvar truth;
  Eigen::MatrixXd e;
  Eigen::MatrixXd y;
};

Fixture make(std::uint64_t seed, int g, int m, int n) {
  std::mt19937_64 rng(seed);
  Fixture f;
  f.truth = random_svar(rng, g, m);
  f.e = draw_noise(rng, n, Eigen::VectorXd::Constant(g, 0.3), NoiseKind::uniform);
  f.y = simulate(f.truth, f.e);
  return f;
}

TEST(Counterfactual, NoInterventionReproducesDataExactly) {
  const Fixture f = make(1, 4, 2, 600);
  CounterfactualQuery q;
  q.from = 2;
  q.to = 599;
  const CounterfactualResult r = counterfactual(model_of(f.truth), f.y, q);
  ASSERT_EQ(r.status, AnalysisStatus::ok) << r.message;
  EXPECT_MATRIX_NEAR(r.counterfactual, r.observed, 1e-12);
  EXPECT_MATRIX_NEAR(r.observed, f.y.middleRows(2, 598), 0.0);
  // With the true model, abduction recovers the true noise.
  EXPECT_MATRIX_NEAR(r.noise, f.e.middleRows(2, 598), 1e-12);
}

TEST(Counterfactual, ReproductionHoldsForAnyInvertibleModel) {
  // Reproduction is a property of abduction + prediction, not of the model being right: a wrong model with
  // instantaneous links both ways (invertible) that is even explosive, and time-varying models, must
  // reproduce the data too (bit for bit: the deviation form keeps d = 0 exactly).
  const Fixture f = make(2, 3, 1, 300);
  StructuralModel wrong = zero_model(3, 1);
  wrong.a0 << 0, 0.4, -0.3, 0.5, 0, 0.2, -0.6, 0.1, 0;
  wrong.lags[0] << 0.9, -0.5, 0.2, 0.3, 0.7, -0.4, 0.1, 0.2, 0.8;
  CounterfactualQuery q;
  q.from = 1;
  q.to = 299;
  ASSERT_EQ(check_dynamics(wrong).status, AnalysisStatus::unstable);
  CounterfactualResult r = counterfactual(wrong, f.y, q);
  ASSERT_EQ(r.status, AnalysisStatus::ok);
  EXPECT_MATRIX_NEAR(r.counterfactual, r.observed, 0.0);

  std::vector<StructuralModel> per_sample;
  for (int n = q.from; n <= q.to; ++n) {
    StructuralModel mn = wrong;
    mn.a0 *= 1.0 + 0.001 * n;
    per_sample.push_back(mn);
  }
  r = counterfactual(per_sample, f.y, q);
  ASSERT_EQ(r.status, AnalysisStatus::ok);
  EXPECT_MATRIX_NEAR(r.counterfactual, r.observed, 0.0);
}

TEST(Counterfactual, HoldMatchesTrueSystemWithSameNoise) {
  const Fixture f = make(3, 4, 2, 500);
  for (int j = 0; j < 4; ++j) {
    CounterfactualQuery q;
    q.from = 200;
    q.to = 349;
    q.holds = {{j, 0.0}};
    const CounterfactualResult r = counterfactual(model_of(f.truth), f.y, q);
    ASSERT_EQ(r.status, AnalysisStatus::ok) << r.message;
    // Truth: the same noise, channel j forced to 0 inside the window only.
    Eigen::MatrixXd forced = no_force(500, 4);
    forced.block(200, j, 150, 1).setZero();
    const Eigen::MatrixXd truth = simulate(f.truth, f.e, &forced);
    EXPECT_MATRIX_NEAR(r.counterfactual, truth.middleRows(200, 150), 1e-10);
    EXPECT_TRUE((r.counterfactual.col(j).array() == 0.0).all());
  }
}

TEST(Counterfactual, TwoHolds) {
  const Fixture f = make(4, 4, 1, 300);
  CounterfactualQuery q;
  q.from = 100;
  q.to = 199;
  q.holds = {{f.truth.order[0], 1.0}, {f.truth.order[2], -0.5}};
  const CounterfactualResult r = counterfactual(model_of(f.truth), f.y, q);
  ASSERT_EQ(r.status, AnalysisStatus::ok);
  Eigen::MatrixXd forced = no_force(300, 4);
  forced.block(100, f.truth.order[0], 100, 1).setConstant(1.0);
  forced.block(100, f.truth.order[2], 100, 1).setConstant(-0.5);
  EXPECT_MATRIX_NEAR(r.counterfactual, simulate(f.truth, f.e, &forced).middleRows(100, 100), 1e-10);
}

TEST(Counterfactual, StatusesAndErrors) {
  const Fixture f = make(5, 3, 2, 100);
  const StructuralModel m = model_of(f.truth);
  CounterfactualQuery q;
  q.from = 1;  // needs 2 samples of history
  q.to = 50;
  EXPECT_THROW(counterfactual(m, f.y, q), std::invalid_argument);
  q.from = 2;
  q.to = 100;
  EXPECT_THROW(counterfactual(m, f.y, q), std::invalid_argument);
  q.to = 50;
  q.holds = {{1, 0.0}, {1, 2.0}};
  EXPECT_THROW(counterfactual(m, f.y, q), std::invalid_argument);
  q.holds = {{3, 0.0}};
  EXPECT_THROW(counterfactual(m, f.y, q), std::invalid_argument);
  q.holds.clear();
  EXPECT_THROW(counterfactual(std::vector<StructuralModel>(3, m), f.y, q), std::invalid_argument);

  Eigen::MatrixXd bad = f.y;
  bad(1, 0) = std::numeric_limits<double>::quiet_NaN();  // in the history of sample 2
  EXPECT_EQ(counterfactual(m, bad, q).status, AnalysisStatus::non_finite_input);

  StructuralModel loop = zero_model(3, 2);
  loop.a0(0, 1) = 1.0;
  loop.a0(1, 0) = 1.0;
  const CounterfactualResult r = counterfactual(loop, f.y, q);
  EXPECT_EQ(r.status, AnalysisStatus::not_identifiable);
  EXPECT_TRUE(std::isnan(r.counterfactual(0, 0)));
  // Holding one end of the loop makes it solvable.
  q.holds = {{0, 0.0}};
  EXPECT_EQ(counterfactual(loop, f.y, q).status, AnalysisStatus::ok);
}

// Stability travels with the answer: the companion spectral radius of the model with the held channel's
// equation replaced. y1 = 0.9 y1[n-1] + e1, y2 = 0.5 y1 + 0.7 y2[n-1] + e2: holding y1 leaves y2's 0.7;
// without a hold nothing is re-simulated (0); holding y2 leaves y1's 0.9.
TEST(Counterfactual, ReportsTheSpectralRadiusOfTheIntervenedModel) {
  StructuralModel m = zero_model(2, 1);
  m.a0(1, 0) = 0.5;
  m.lags[0](0, 0) = 0.9;
  m.lags[0](1, 1) = 0.7;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd data(20, 2);
  for (Eigen::Index i = 0; i < data.size(); ++i) data.data()[i] = normal(rng);
  CounterfactualQuery q;
  q.from = 1;
  q.to = 19;
  EXPECT_DOUBLE_EQ(counterfactual(m, data, q).spectral_radius, 0.0);
  q.holds = {{0, 1.0}};
  EXPECT_NEAR(counterfactual(m, data, q).spectral_radius, 0.7, 1e-12);
  q.holds = {{1, 1.0}};
  EXPECT_NEAR(counterfactual(m, data, q).spectral_radius, 0.9, 1e-12);
}

}  // namespace
