#include "causal/analysis/direct_lingam.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "matrix_asserts.hpp"
#include "svar_sim.hpp"

using namespace causal::analysis;
using causal::analysis::test::draw_noise;
using causal::analysis::test::NoiseKind;
using causal::analysis::test::random_svar;
using causal::analysis::test::TrueSvar;

namespace {

constexpr double kGaussianEntropy = 1.4189385332046727;  // (1 + log 2 pi) / 2

Eigen::VectorXd standardized(const Eigen::VectorXd& v) {
  const Eigen::VectorXd c = v.array() - v.mean();
  return c / std::sqrt(c.squaredNorm() / static_cast<double>(c.size()));
}

TEST(DirectLingam, EntropyApproximationIsMaximalForGaussian) {
  std::mt19937_64 rng(1);
  const int n = 200000;
  const Eigen::VectorXd gauss = standardized(draw_noise(rng, n, Eigen::VectorXd::Ones(1), NoiseKind::gaussian).col(0));
  const Eigen::VectorXd uni = standardized(draw_noise(rng, n, Eigen::VectorXd::Ones(1), NoiseKind::uniform).col(0));
  const Eigen::VectorXd lap = standardized(draw_noise(rng, n, Eigen::VectorXd::Ones(1), NoiseKind::laplace).col(0));
  EXPECT_NEAR(entropy_approximation(gauss), kGaussianEntropy, 2e-3);
  // Any non-Gaussian unit-variance law has lower entropy (uniform: log(2 sqrt 3) = 1.2425 exactly; the
  // approximation only has to keep the ranking).
  EXPECT_LT(entropy_approximation(uni), kGaussianEntropy - 0.02);
  EXPECT_LT(entropy_approximation(lap), kGaussianEntropy - 0.02);
}

TEST(DirectLingam, PairwiseRatioPointsFromCauseToEffect) {
  std::mt19937_64 rng(2);
  const Eigen::MatrixXd e = draw_noise(rng, 5000, Eigen::VectorXd::Ones(2), NoiseKind::uniform);
  const Eigen::VectorXd cause = e.col(0);
  const Eigen::VectorXd effect = 0.8 * cause + e.col(1);
  const double forward = pairwise_likelihood_ratio(cause, effect);
  EXPECT_GT(forward, 0.0);
  EXPECT_NEAR(pairwise_likelihood_ratio(effect, cause), -forward, 1e-12);  // antisymmetric by (L2)
}

TEST(DirectLingam, RecoversOrderAndCoefficientsOfStaticDag) {
  std::mt19937_64 rng(3);
  const int g = 5;
  // Static DAG via the simulator with zero lags.
  TrueSvar s = random_svar(rng, g, 1, 0.4, 0.8, 0.0, 0.0);
  s.lags[0].setZero();
  const Eigen::MatrixXd e = draw_noise(rng, 5000, Eigen::VectorXd::Ones(g), NoiseKind::laplace);
  const Eigen::MatrixXd x = causal::analysis::test::simulate(s, e);
  const DirectLingamResult r = direct_lingam(x);
  EXPECT_EQ(r.order, s.order);
  EXPECT_MATRIX_NEAR(r.b0, s.a0, 0.06);
  // Disturbances are e up to centering and estimation error.
  const Eigen::MatrixXd ec = e.rowwise() - e.colwise().mean();
  EXPECT_LT((r.disturbances - ec).cwiseAbs().maxCoeff() / ec.cwiseAbs().maxCoeff(), 0.2);
}

TEST(DirectLingam, RejectsBadInput) {
  EXPECT_THROW(direct_lingam(Eigen::MatrixXd::Zero(5, 2)), std::invalid_argument);  // too few rows
  std::mt19937_64 rng(4);
  Eigen::MatrixXd x = draw_noise(rng, 100, Eigen::VectorXd::Ones(2), NoiseKind::uniform);
  x.col(1).setConstant(3.0);
  EXPECT_THROW(direct_lingam(x), std::invalid_argument);  // constant variable
  x.col(1) = x.col(0);
  x(10, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(direct_lingam(x), std::invalid_argument);
}

TEST(DirectLingam, SingleVariable) {
  std::mt19937_64 rng(5);
  const DirectLingamResult r = direct_lingam(draw_noise(rng, 50, Eigen::VectorXd::Ones(1), NoiseKind::uniform));
  EXPECT_EQ(r.order, std::vector<int>{0});
  EXPECT_EQ(r.b0(0, 0), 0.0);
}

}  // namespace
