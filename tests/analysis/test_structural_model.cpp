#include "causal/analysis/structural_model.hpp"

#include <gtest/gtest.h>

#include <causal/estimation/svar_kalman_filter.hpp>
#include <causal/estimation/svar_layout.hpp>

#include <cmath>
#include <random>

#include "matrix_asserts.hpp"

using causal::estimation::ModelSpec;
using causal::estimation::NoiseParams;
using causal::estimation::SvarKalmanFilter;
using causal::estimation::SvarLayout;
using namespace causal::analysis;

namespace {

TEST(StructuralModel, AssemblesEveryFactorIntoItsSlot) {
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  spec.lag_order = 2;
  spec.include_self_lags = true;
  const causal::estimation::SvarLayout layout(spec);
  Eigen::VectorXd x(layout.total_factors());
  for (int i = 0; i < x.size(); ++i) x(i) = 1.0 + i;
  const StructuralModel m = assemble_structural_model(layout, x);
  ASSERT_EQ(m.channels(), 3);
  ASSERT_EQ(m.lag_order(), 2);
  // Truth from the layout's own index lookup (not from regressors()).
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(m.a0(k, k), 0.0);
    for (int j = 0; j < 3; ++j) {
      if (j != k) {
        EXPECT_EQ(m.a0(k, j), x(layout.offset(k) + layout.factor_index(k, j, 0)));
      }
      for (int l = 1; l <= 2; ++l) EXPECT_EQ(m.lags[l - 1](k, j), x(layout.offset(k) + layout.factor_index(k, j, l)));
    }
  }
  ASSERT_MATRIX_NEAR(factors_from_model(layout, m), x, 0.0);
}

TEST(StructuralModel, FactorNamesMatchHouseConvention) {
  const causal::estimation::SvarLayout layout(causal::estimation::ModelSpec{});  // G=4, M=1, no self lags: x12 x13 x14 xL12 xL13 xL14 x21 ...
  Eigen::VectorXd x = Eigen::VectorXd::Zero(layout.total_factors());
  x(0) = 0.5;   // x12: y2 -> y1 instantaneous
  x(3) = -0.25; // xL12: y2[n-1] -> y1
  x(6) = 0.75;  // x21
  const StructuralModel m = assemble_structural_model(layout, x);
  EXPECT_EQ(layout.factor_names()[0], "x12");
  EXPECT_EQ(m.a0(0, 1), 0.5);
  EXPECT_EQ(m.lags[0](0, 1), -0.25);
  EXPECT_EQ(m.a0(1, 0), 0.75);
  EXPECT_EQ(m.lags[0](0, 0), 0.0);  // self lag not in this layout: structural zero
  EXPECT_THROW(assemble_structural_model(layout, Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

TEST(StructuralModel, MaskedLinksAreZero) {
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  spec.instantaneous_allowed = {{false, false, false}, {true, false, false}, {true, true, false}};
  const causal::estimation::SvarLayout layout(spec);
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(layout.total_factors());
  const StructuralModel m = assemble_structural_model(layout, x);
  Eigen::MatrixXd expected(3, 3);
  expected << 0, 0, 0, 1, 0, 0, 1, 1, 0;
  ASSERT_MATRIX_NEAR(m.a0, expected, 0.0);
}

TEST(StructuralModel, DynamicsCheckAgainstClosedForms) {
  StructuralModel m = zero_model(2, 1);
  m.a0(1, 0) = 0.5;
  m.lags[0] = 0.5 * Eigen::MatrixXd::Identity(2, 2);
  // B1 = (I - A0)^{-1} A1 = [[0.5, 0], [0.25, 0.5]]: eigenvalues 0.5, 0.5.
  DynamicsCheck c = check_dynamics(m);
  EXPECT_EQ(c.status, AnalysisStatus::ok);
  EXPECT_NEAR(c.spectral_radius, 0.5, 1e-6);
  Eigen::MatrixXd b1(2, 2);
  b1 << 0.5, 0, 0.25, 0.5;
  ASSERT_MATRIX_NEAR(companion_matrix(m), b1, 1e-14);

  m.lags[0](0, 0) = 1.0;  // unit root
  c = check_dynamics(m);
  EXPECT_EQ(c.status, AnalysisStatus::unstable);
  EXPECT_NEAR(c.spectral_radius, 1.0, 1e-9);
  m.lags[0](0, 0) = 1.2;  // explosive
  EXPECT_EQ(check_dynamics(m).status, AnalysisStatus::unstable);

  // Instantaneous loop with gain 1: y1 = y2 + e1, y2 = y1 + e2 has no solution.
  StructuralModel loop = zero_model(2, 1);
  loop.a0 << 0, 1, 1, 0;
  c = check_dynamics(loop);
  EXPECT_EQ(c.status, AnalysisStatus::not_identifiable);
  EXPECT_FALSE(c.message.empty());
  EXPECT_THROW(companion_matrix(loop), std::invalid_argument);

  loop.a0(0, 1) = std::nan("");
  EXPECT_EQ(check_dynamics(loop).status, AnalysisStatus::non_finite_input);
}

TEST(StructuralModel, SecondOrderCompanion) {
  // Scalar-like AR(2) on channel 0: y = 0.5 y[n-1] + 0.3 y[n-2]: roots of z^2 - 0.5 z - 0.3.
  StructuralModel m = zero_model(2, 2);
  m.lags[0](0, 0) = 0.5;
  m.lags[1](0, 0) = 0.3;
  const double root = (0.5 + std::sqrt(0.25 + 1.2)) / 2.0;
  EXPECT_NEAR(check_dynamics(m).spectral_radius, root, 1e-9);
}

TEST(StructuralModel, GraphSurgeryCutsRowsOnly) {
  StructuralModel m = zero_model(3, 1);
  m.a0 << 0, 1, 2, 3, 0, 4, 5, 6, 0;
  m.lags[0].setConstant(7.0);
  const StructuralModel cut = graph_surgery(m, {1});
  EXPECT_TRUE(cut.a0.row(1).isZero());
  EXPECT_TRUE(cut.lags[0].row(1).isZero());
  EXPECT_EQ(cut.a0(0, 1), 1.0);  // column 1 (effects OF y2) kept
  EXPECT_EQ(cut.a0(2, 1), 6.0);
  EXPECT_THROW(graph_surgery(m, {3}), std::invalid_argument);
}

TEST(StructuralModel, ValidateRejectsBadShapes) {
  StructuralModel m = zero_model(2, 1);
  m.a0(0, 0) = 0.1;
  EXPECT_THROW(validate_model(m), std::invalid_argument);
  m = zero_model(2, 1);
  m.lags[0] = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(validate_model(m), std::invalid_argument);
}

TEST(StructuralModel, PosteriorFromFilterMatchesFilterState) {
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  const causal::estimation::SvarLayout layout(spec);
  causal::estimation::SvarKalmanFilter filter(layout, {causal::estimation::NoiseParams{1e-4, 0.1, 1.0}});
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int t = 0; t < 50; ++t) {
    const double y[3] = {n01(rng), n01(rng), n01(rng)};
    filter.step(y);
  }
  const FactorPosterior post = posterior_from_filter(layout, filter);
  Eigen::VectorXd all(layout.total_factors());
  filter.estimates(all.data());
  ASSERT_MATRIX_NEAR(post.mean, all, 0.0);
  ASSERT_EQ(post.blocks.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    ASSERT_MATRIX_NEAR(post.blocks[k], filter.covariance(k), 0.0);
    EXPECT_SPD(post.blocks[k], 0.0);
  }
  const FactorPosterior diag = posterior_from_std_devs(layout, all, Eigen::VectorXd::Constant(all.size(), 0.1));
  ASSERT_MATRIX_NEAR(diag.blocks[1], 0.01 * Eigen::MatrixXd::Identity(layout.factor_count(1), layout.factor_count(1)),
                     1e-15);
}

}  // namespace
