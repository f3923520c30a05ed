// sensor-sim's generator: determinism (same seed, same samples, whatever the frame cut), the structure it
// promises (acyclic instantaneous part, no self-lags, stable), and its known factors recovered by an
// independent OLS fit of a long run (truth = the model it reports; estimate = plain least squares here).
#include "svar_generator.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

using causal::sim::SvarGenerator;
using causal::sim::SvarModel;
using causal::sim::make_group_model;

namespace {

Eigen::MatrixXd run(std::uint64_t seed, std::uint64_t group, int g, int m, Eigen::Index n) {
  SvarGenerator gen(make_group_model(seed, group, g, m), seed, group);
  Eigen::MatrixXd y;
  gen.next(n, y);
  return y;
}

// Dense companion matrix of the reduced form, built here with an explicit inverse (independent of the library).
double spectral_radius(const SvarModel& s) {
  const int g = s.channels(), m = s.lag_order();
  const Eigen::MatrixXd inv = (Eigen::MatrixXd::Identity(g, g) - s.instantaneous).inverse();
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(g * m, g * m);
  for (int l = 0; l < m; ++l) c.block(0, l * g, g, g) = inv * s.lags[static_cast<std::size_t>(l)];
  if (m > 1) c.block(g, 0, g * (m - 1), g * (m - 1)).setIdentity();
  return Eigen::EigenSolver<Eigen::MatrixXd>(c).eigenvalues().cwiseAbs().maxCoeff();
}

}  // namespace

TEST(SvarGenerator, SameSeedSameSamplesWhateverTheFrameCut) {
  const Eigen::MatrixXd whole = run(7, 3, 4, 2, 1000);
  SvarGenerator pieces(make_group_model(7, 3, 4, 2), 7, 3);
  Eigen::MatrixXd joined(1000, 4), part;
  for (int i = 0; i < 10; ++i) {
    pieces.next(100, part);
    joined.middleRows(i * 100, 100) = part;
  }
  EXPECT_EQ(pieces.samples_generated(), 1000u);
  EXPECT_TRUE(whole.cwiseEqual(joined).all()) << "frame cut changed the samples";
  EXPECT_TRUE(whole.cwiseEqual(run(7, 3, 4, 2, 1000)).all()) << "same seed, different samples";
  EXPECT_TRUE(whole.allFinite());
}

TEST(SvarGenerator, GroupsAndSeedsDiffer) {
  const Eigen::MatrixXd a = run(7, 3, 4, 1, 200);
  EXPECT_GT((a - run(7, 4, 4, 1, 200)).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_GT((a - run(8, 3, 4, 1, 200)).cwiseAbs().maxCoeff(), 0.1);
  const SvarModel m3 = make_group_model(7, 3, 4, 1), m4 = make_group_model(7, 4, 4, 1);
  EXPECT_GT((m3.instantaneous - m4.instantaneous).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SvarGenerator, ModelIsAcyclicWithoutSelfLagsAndStable) {
  for (std::uint64_t group = 0; group < 50; ++group) {
    const SvarModel s = make_group_model(11, group, 6, 2);
    ASSERT_EQ(s.channels(), 6);
    ASSERT_EQ(s.lag_order(), 2);
    for (int k = 0; k < 6; ++k) {
      for (int j = k; j < 6; ++j) EXPECT_EQ(s.instantaneous(k, j), 0.0) << "x" << k + 1 << j + 1;
      for (int j = 0; j < k; ++j) {
        EXPECT_GE(std::abs(s.instantaneous(k, j)), 0.2);
        EXPECT_LE(std::abs(s.instantaneous(k, j)), 0.5);
      }
      for (const auto& a : s.lags) EXPECT_EQ(a(k, k), 0.0) << "self lag of channel " << k + 1;
      EXPECT_GE(s.noise_sd[k], 0.5);
      EXPECT_LE(s.noise_sd[k], 1.5);
    }
    const double radius = spectral_radius(s);
    EXPECT_LT(radius, 0.9) << "group " << group;
    EXPECT_NEAR(causal::sim::companion_spectral_radius(s), radius, 1e-9);
  }
}

// Outcome k regressed on its instantaneous parents (j < k) and every lagged other channel: the structural
// equation exactly, so OLS is consistent for the true factors. Each estimate must lie within 5 standard
// errors of the truth, and the noise variance within 3 %.
TEST(SvarGenerator, KnownFactorsAreRecoveredByOlsOfALongRun) {
  const int g = 4, m = 2;
  const Eigen::Index n = 200000;
  const SvarModel truth = make_group_model(2026, 17, g, m);
  const Eigen::MatrixXd y = run(2026, 17, g, m, n);
  double worst = 0.0;
  for (int k = 0; k < g; ++k) {
    std::vector<std::pair<int, int>> regressors;  // (lag, channel); lag 0 = instantaneous
    for (int j = 0; j < k; ++j) regressors.emplace_back(0, j);
    for (int l = 1; l <= m; ++l)
      for (int j = 0; j < g; ++j)
        if (j != k) regressors.emplace_back(l, j);
    const Eigen::Index rows = n - m;
    Eigen::MatrixXd x(rows, static_cast<Eigen::Index>(regressors.size()));
    for (std::size_t c = 0; c < regressors.size(); ++c)
      x.col(static_cast<Eigen::Index>(c)) = y.col(regressors[c].second).segment(m - regressors[c].first, rows);
    const Eigen::VectorXd target = y.col(k).tail(rows);
    const Eigen::VectorXd b = x.colPivHouseholderQr().solve(target);
    const Eigen::VectorXd resid = target - x * b;
    const double s2 = resid.squaredNorm() / static_cast<double>(rows - x.cols());
    const Eigen::MatrixXd cov = s2 * (x.transpose() * x).inverse();
    for (std::size_t c = 0; c < regressors.size(); ++c) {
      const auto [lag, j] = regressors[c];
      const double true_value = lag == 0 ? truth.instantaneous(k, j) : truth.lags[static_cast<std::size_t>(lag - 1)](k, j);
      const auto i = static_cast<Eigen::Index>(c);
      const double se = std::sqrt(cov(i, i));
      EXPECT_LT(std::abs(b[i] - true_value), 5.0 * se)
          << "outcome " << k + 1 << ", channel " << j + 1 << ", lag " << lag << ": " << b[i] << " vs " << true_value;
      worst = std::max(worst, std::abs(b[i] - true_value));
    }
    EXPECT_NEAR(s2, truth.noise_sd[k] * truth.noise_sd[k], 0.03 * truth.noise_sd[k] * truth.noise_sd[k]);
  }
  EXPECT_LT(worst, 0.03);  // the standard errors above are small, not the test vacuous
}

TEST(SvarGenerator, FactorsAreDescribedByTheirReadmeNames) {
  SvarModel s;
  s.instantaneous = Eigen::MatrixXd::Zero(2, 2);
  s.instantaneous(1, 0) = 0.25;
  s.lags = {Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 2)};
  s.lags[0](0, 1) = -0.125;
  s.lags[1](1, 0) = 0.5;
  s.noise_sd = Eigen::VectorXd::Ones(2);
  EXPECT_EQ(causal::sim::describe_factors(s),
            "x12=+0.000 x21=+0.250 xL12=-0.125 xL21=+0.000 xL212=+0.000 xL221=+0.500");
}

TEST(SvarGenerator, RefusesImpossibleShapes) {
  EXPECT_THROW(make_group_model(1, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW(make_group_model(1, 0, 4, 0), std::invalid_argument);
}
