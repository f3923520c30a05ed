// Statistics used to design the alarm thresholds, checked against closed forms, published tables and
// Monte Carlo simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "causal/alarms/statistics.hpp"

using namespace causal::alarms;

TEST(AlarmStatistics, MedianOddEvenAndNaN) {
  EXPECT_DOUBLE_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_DOUBLE_EQ(median({std::nan(""), 5.0, 1.0, std::numeric_limits<double>::infinity(), 3.0}), 3.0);
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(AlarmStatistics, RobustStatsRecoverGaussianSigmaAndIgnoreOutliers) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(10.0, 2.0);
  std::vector<double> v(20000);
  for (auto& x : v) x = n(rng);
  // 5 % gross outliers must not move the robust estimates much (MAD breakdown point is 50 %).
  for (std::size_t i = 0; i < v.size(); i += 20) v[i] = 1e6;
  const RobustStats s = robust_stats(v);
  ASSERT_TRUE(s.valid);
  EXPECT_NEAR(s.location, 10.0, 0.15);
  EXPECT_NEAR(s.scale, 2.0, 0.2);
}

TEST(AlarmStatistics, RobustStatsFallbacksKeepScalePositive) {
  const RobustStats c = robust_stats({5.0, 5.0, 5.0, 5.0});
  ASSERT_TRUE(c.valid);
  EXPECT_GT(c.scale, 0.0);
  EXPECT_NEAR(c.scale, 5e-6, 1e-12);  // relative floor 1e-6 * |median|
  // MAD = 0 but the data are not constant: falls back to the standard deviation.
  const RobustStats q = robust_stats({1.0, 1.0, 1.0, 1.0, 1.0, 2.0});
  EXPECT_NEAR(q.scale, std::sqrt((5 * (1.0 / 36) + 25.0 / 36) / 5.0), 1e-12);
  EXPECT_FALSE(robust_stats({1.0}).valid);
}

TEST(AlarmStatistics, LagOneAutocorrelationOfAr1) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> v(50000);
  double x = 0.0;
  for (auto& y : v) y = x = 0.6 * x + n(rng);
  EXPECT_NEAR(robust_stats(v).lag1_autocorr, 0.6, 0.02);
}

TEST(AlarmStatistics, NormalQuantileMatchesTables) {
  // Reference values: standard normal tables (e.g. Abramowitz & Stegun 26.2).
  EXPECT_NEAR(normal_upper_quantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(normal_upper_quantile(0.025), 1.959963984540054, 1e-9);
  EXPECT_NEAR(normal_upper_quantile(0.975), -1.959963984540054, 1e-9);
  EXPECT_NEAR(normal_upper_quantile(1e-3), 3.090232306167813, 1e-9);
  EXPECT_NEAR(normal_upper_quantile(1e-6), 4.753424308822899, 1e-8);
  EXPECT_NEAR(normal_upper_quantile(1e-9), 5.997807015007686, 1e-7);
  // Round trip through erfc.
  for (double p : {0.3, 0.01, 1e-4, 1e-7}) EXPECT_NEAR(0.5 * std::erfc(normal_upper_quantile(p) / std::sqrt(2.0)), p, 1e-9 * p + 1e-15);
  EXPECT_THROW(normal_upper_quantile(0.0), std::invalid_argument);
}

TEST(AlarmStatistics, ChiSquareQuantileMatchesTables) {
  // Reference: chi-square tables (NIST/SEMATECH e-Handbook 1.3.6.7.4). Wilson-Hilferty: < 1 % from 10
  // degrees of freedom; at 4 it is within 2 % and on the high side (fewer false alarms, never more).
  struct Row { int dof; double p, x; };
  for (const Row r : {Row{10, 0.05, 18.307}, Row{10, 0.001, 29.588}, Row{12, 0.01, 26.217}, Row{30, 0.001, 59.703},
                      Row{100, 0.01, 135.807}}) {
    EXPECT_NEAR(chi_square_upper_quantile(r.dof, r.p), r.x, 0.01 * r.x) << "dof " << r.dof << " p " << r.p;
  }
  const double q4 = chi_square_upper_quantile(4, 0.001);
  EXPECT_GE(q4, 18.467);
  EXPECT_LE(q4, 1.02 * 18.467);
}

TEST(AlarmStatistics, SiegmundArlMatchesTabulatedCusum) {
  // Tabulated one-sided CUSUM ARL0 (Montgomery, Introduction to Statistical Quality Control, Table 9.3,
  // k = 0.5): h = 4 -> 336, h = 5 -> 930. Siegmund's approximation is within a few percent.
  EXPECT_NEAR(cusum_arl0(0.5, 4.0), 336.0, 0.03 * 336.0);
  EXPECT_NEAR(cusum_arl0(0.5, 5.0), 930.0, 0.03 * 930.0);
  const double h = cusum_threshold_for_arl0(1.5, 1e6);
  EXPECT_NEAR(cusum_arl0(1.5, h), 1e6, 1.0);
  EXPECT_GT(h, cusum_threshold_for_arl0(1.5, 1e4));
}

TEST(AlarmStatistics, SiegmundArlAgreesWithMonteCarlo) {
  // Independent check of the ARL approximation at the project's k by simulating the plain CUSUM.
  const double k = 1.5, target = 200.0;
  const double h = cusum_threshold_for_arl0(k, target);
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> n(0.0, 1.0);
  double total = 0.0;
  const int runs = 4000;
  for (int r = 0; r < runs; ++r) {
    double s = 0.0;
    long t = 0;
    do {
      ++t;
      s = std::max(0.0, s + n(rng) - k);
    } while (s < h);
    total += static_cast<double>(t);
  }
  // Standard error of the mean run length ~ ARL / sqrt(runs) = 1.6 %; Siegmund's error is a few percent.
  EXPECT_NEAR(total / runs, target, 0.12 * target);
}
