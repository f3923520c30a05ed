#include "causal/analysis/var_fit.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <random>

#include "matrix_asserts.hpp"
#include "svar_sim.hpp"

using namespace causal::analysis;
using causal::analysis::test::draw_noise;
using causal::analysis::test::NoiseKind;

namespace {

// Reduced-form VAR(2) data with intercept: y[n] = c + P1 y[n-1] + P2 y[n-2] + u[n].
Eigen::MatrixXd simulate_var2(const Eigen::VectorXd& c, const Eigen::MatrixXd& p1, const Eigen::MatrixXd& p2,
                              const Eigen::MatrixXd& u) {
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(u.rows(), u.cols());
  for (int n = 0; n < u.rows(); ++n) {
    Eigen::VectorXd v = c + u.row(n).transpose();
    if (n >= 1) v += p1 * y.row(n - 1).transpose();
    if (n >= 2) v += p2 * y.row(n - 2).transpose();
    y.row(n) = v.transpose();
  }
  return y;
}

TEST(VarFit, RecoversKnownCoefficients) {
  std::mt19937_64 rng(11);
  Eigen::MatrixXd p1(3, 3), p2(3, 3);
  p1 << 0.5, 0.1, 0.0, -0.2, 0.3, 0.1, 0.0, 0.2, 0.4;
  p2 << 0.1, 0.0, 0.0, 0.0, -0.1, 0.0, 0.05, 0.0, 0.1;
  const Eigen::VectorXd c = Eigen::Vector3d(1.0, -0.5, 0.25);
  const Eigen::MatrixXd u = draw_noise(rng, 20000, Eigen::VectorXd::Constant(3, 0.5), NoiseKind::gaussian);
  const Eigen::MatrixXd y = simulate_var2(c, p1, p2, u);
  const VarFit fit = fit_var_least_squares(y, 2);
  ASSERT_EQ(fit.coefficients.size(), 2u);
  // Standard error of each coefficient ~ 0.5 / sqrt(20000 var(y)) < 0.005: 0.02 is > 4 sigma.
  EXPECT_MATRIX_NEAR(fit.coefficients[0], p1, 0.02);
  EXPECT_MATRIX_NEAR(fit.coefficients[1], p2, 0.02);
  EXPECT_MATRIX_NEAR(fit.intercept, c, 0.05);
  EXPECT_EQ(fit.residuals.rows(), 19998);
  EXPECT_EQ(fit.rows_skipped, 0);
  // Residual covariance close to the true 0.25 I.
  const Eigen::MatrixXd cov = fit.residuals.transpose() * fit.residuals / static_cast<double>(fit.residuals.rows());
  EXPECT_MATRIX_NEAR(cov, 0.25 * Eigen::MatrixXd::Identity(3, 3), 0.02);
}

TEST(VarFit, MatchesNormalEquationsReference) {
  std::mt19937_64 rng(3);
  const Eigen::MatrixXd y = draw_noise(rng, 60, Eigen::VectorXd::Ones(2), NoiseKind::uniform);
  const VarFit fit = fit_var_least_squares(y, 1);
  // Dense reference: beta = (X^T X)^{-1} X^T Y with X = [1, y[n-1]].
  Eigen::MatrixXd x(59, 3);
  for (int n = 1; n < 60; ++n) x.row(n - 1) << 1.0, y(n - 1, 0), y(n - 1, 1);
  const Eigen::MatrixXd beta = (x.transpose() * x).ldlt().solve(x.transpose() * y.bottomRows(59));
  EXPECT_MATRIX_NEAR(fit.intercept, beta.row(0).transpose(), 1e-12);
  EXPECT_MATRIX_NEAR(fit.coefficients[0], beta.bottomRows(2).transpose(), 1e-12);
  EXPECT_MATRIX_NEAR(fit.residuals, y.bottomRows(59) - x * beta, 1e-12);
}

TEST(VarFit, SkipsWindowsWithNonFiniteValues) {
  std::mt19937_64 rng(5);
  Eigen::MatrixXd y = draw_noise(rng, 100, Eigen::VectorXd::Ones(2), NoiseKind::gaussian);
  y(50, 1) = std::numeric_limits<double>::quiet_NaN();
  const VarFit fit = fit_var_least_squares(y, 2);
  // Sample 50 spoils the windows ending at 50, 51, 52.
  EXPECT_EQ(fit.rows_skipped, 3);
  EXPECT_EQ(fit.residuals.rows(), 98 - 3);
  EXPECT_TRUE(fit.residuals.allFinite());
  for (int n : fit.rows_used) EXPECT_TRUE(n < 50 || n > 52);
}

TEST(VarFit, RejectsBadInput) {
  EXPECT_THROW(fit_var_least_squares(Eigen::MatrixXd::Zero(100, 2), 0), std::invalid_argument);
  EXPECT_THROW(fit_var_least_squares(Eigen::MatrixXd::Zero(7, 2), 1), std::invalid_argument);
}

TEST(VarFit, NoInterceptOption) {
  std::mt19937_64 rng(9);
  const Eigen::MatrixXd y = draw_noise(rng, 200, Eigen::VectorXd::Ones(2), NoiseKind::gaussian);
  const VarFit fit = fit_var_least_squares(y, 1, false);
  EXPECT_FALSE(fit.has_intercept);
  EXPECT_TRUE(fit.intercept.isZero());
}

}  // namespace
