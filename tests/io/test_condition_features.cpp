#include "causal/io/condition_features.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "causal/io/ims_directory.hpp"
#include "io_test_util.hpp"
#include "matrix_asserts.hpp"
#include "real_stats.hpp"

using causal::io::compute_condition_feature;
using causal::io::ConditionFeature;
using causal::io::parse_condition_feature;

namespace {

constexpr double kPi = 3.14159265358979323846;
const ConditionFeature kAll[] = {ConditionFeature::Rms, ConditionFeature::MeanAbs, ConditionFeature::Kurtosis,
                                 ConditionFeature::Peak};

// Reference implementation in long double, straight from the definitions (population moments).
double reference(const Eigen::VectorXd& x, ConditionFeature f) {
  const auto n = static_cast<long double>(x.size());
  long double s = 0, s2 = 0, sa = 0, pk = 0;
  for (double v : x) {
    s += v;
    s2 += static_cast<long double>(v) * v;
    sa += std::fabs(static_cast<long double>(v));
    pk = std::max(pk, std::fabs(static_cast<long double>(v)));
  }
  const long double mean = s / n;
  long double m2 = 0, m4 = 0;
  for (double v : x) {
    const long double d = v - mean;
    m2 += d * d;
    m4 += d * d * d * d;
  }
  switch (f) {
    case ConditionFeature::Rms: return static_cast<double>(std::sqrt(s2 / n));
    case ConditionFeature::MeanAbs: return static_cast<double>(sa / n);
    case ConditionFeature::Kurtosis: return static_cast<double>(n * m4 / (m2 * m2));
    case ConditionFeature::Peak: return static_cast<double>(pk);
  }
  return NAN;
}

}  // namespace

TEST(ConditionFeatures, Names) {
  for (ConditionFeature f : kAll) EXPECT_EQ(parse_condition_feature(causal::io::to_string(f)), f);
  EXPECT_EQ(causal::io::to_string(ConditionFeature::Rms), "rms");
  EXPECT_EQ(causal::io::to_string(ConditionFeature::MeanAbs), "meanabs");
  EXPECT_EQ(causal::io::to_string(ConditionFeature::Kurtosis), "kurtosis");
  EXPECT_EQ(causal::io::to_string(ConditionFeature::Peak), "peak");
  EXPECT_EQ(parse_condition_feature("RMS"), ConditionFeature::Rms);
  EXPECT_EQ(parse_condition_feature("peakabs"), ConditionFeature::Peak);
  EXPECT_FALSE(parse_condition_feature("skew").has_value());
  EXPECT_FALSE(parse_condition_feature("").has_value());
  EXPECT_EQ(causal::io::derived_column_suffix(ConditionFeature::Peak), "_peakabs");
  EXPECT_EQ(causal::io::derived_column_suffix(ConditionFeature::Kurtosis), "_kurtosis");
}

TEST(ConditionFeatures, SineClosedForms) {
  // x = A sin(2 pi k i / N) over k whole periods: the discrete means of sin^2 and sin^4 are exactly
  // 1/2 and 3/8, so RMS = A/sqrt(2) and kurtosis = (3/8)/(1/2)^2 = 1.5; mean |x| -> 2A/pi; the
  // sample at a quarter period gives peak = A. Column 2 adds a second amplitude and a phase.
  const int n = 20480, k = 5;
  const double a1 = 0.7, a2 = 3.0;
  Eigen::MatrixXd x(n, 2);
  for (int i = 0; i < n; ++i) {
    x(i, 0) = a1 * std::sin(2 * kPi * k * i / n);
    x(i, 1) = a2 * std::sin(2 * kPi * k * i / n + 0.3);
  }
  const Eigen::VectorXd rms = compute_condition_feature(x, ConditionFeature::Rms);
  EXPECT_NEAR(rms(0), a1 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(rms(1), a2 / std::sqrt(2.0), 1e-12);
  const Eigen::VectorXd kurt = compute_condition_feature(x, ConditionFeature::Kurtosis);
  EXPECT_NEAR(kurt(0), 1.5, 1e-10);
  EXPECT_NEAR(kurt(1), 1.5, 1e-10);
  const Eigen::VectorXd ma = compute_condition_feature(x, ConditionFeature::MeanAbs);
  EXPECT_NEAR(ma(0), 2 * a1 / kPi, 1e-6);  // Riemann sum of |sin|: error O(1/N^2)
  EXPECT_NEAR(ma(1), 2 * a2 / kPi, 1e-5);
  EXPECT_NEAR(compute_condition_feature(x, ConditionFeature::Peak)(0), a1, 1e-12);
}

TEST(ConditionFeatures, SquareWaveAndConstant) {
  const int n = 1000;
  Eigen::MatrixXd x(n, 3);
  for (int i = 0; i < n; ++i) {
    x(i, 0) = (i % 2 == 0) ? 1.0 : -1.0;  // +-1 square wave: every moment is 1
    x(i, 1) = -0.1;                       // constant: RMS = mean|x| = peak = |c|, kurtosis undefined
    x(i, 2) = (i % 10 < 5) ? 2.5 : -2.5;
  }
  Eigen::Vector3d expect_rms(1.0, 0.1, 2.5);
  ASSERT_MATRIX_NEAR(compute_condition_feature(x, ConditionFeature::Rms), expect_rms, 1e-13);  // sums of n terms: ~n eps
  ASSERT_MATRIX_NEAR(compute_condition_feature(x, ConditionFeature::MeanAbs), expect_rms, 1e-13);
  ASSERT_MATRIX_NEAR(compute_condition_feature(x, ConditionFeature::Peak), expect_rms, 0.0);
  const Eigen::VectorXd kurt = compute_condition_feature(x, ConditionFeature::Kurtosis);
  EXPECT_NEAR(kurt(0), 1.0, 1e-14);
  EXPECT_TRUE(std::isnan(kurt(1))) << kurt(1);
  EXPECT_NEAR(kurt(2), 1.0, 1e-14);
}

TEST(ConditionFeatures, GaussianKurtosisIsThree) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> gauss(0.0, 2.0);
  const int n = 200000;
  Eigen::MatrixXd x(n, 1);
  for (int i = 0; i < n; ++i) x(i, 0) = gauss(rng);
  // Sampling s.d. of the kurtosis estimate is sqrt(24/n) = 0.011; allow 5 s.d.
  EXPECT_NEAR(compute_condition_feature(x, ConditionFeature::Kurtosis)(0), 3.0, 0.055);
  EXPECT_NEAR(compute_condition_feature(x, ConditionFeature::Rms)(0), 2.0, 0.02);
}

TEST(ConditionFeatures, MatchesLongDoubleReferenceWithLargeOffset) {
  // A large DC offset is where naive raw-moment formulas lose all digits of the kurtosis.
  std::mt19937_64 rng(3);
  std::student_t_distribution<double> heavy(5.0);
  Eigen::MatrixXd x(5000, 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    x(i, 0) = heavy(rng);
    x(i, 1) = 1e4 + 0.01 * heavy(rng);
    x(i, 2) = -3.0 + heavy(rng);
  }
  for (ConditionFeature f : kAll) {
    const Eigen::VectorXd got = compute_condition_feature(x, f);
    for (Eigen::Index c = 0; c < 3; ++c) {
      const double ref = reference(x.col(c), f);
      EXPECT_NEAR(got(c), ref, 1e-9 * std::abs(ref)) << causal::io::to_string(f) << " col " << c;
    }
  }
}

TEST(ConditionFeatures, NonFiniteRowsSkippedAndEmptyIsNan) {
  Eigen::MatrixXd x(4, 2);
  x << 1, 2, NAN, 5, -1, 4, 3, INFINITY;
  // Rows 1 and 3 carry a non-finite value: only rows 0 and 2 count, in both columns.
  Eigen::MatrixXd kept(2, 2);
  kept << 1, 2, -1, 4;
  for (ConditionFeature f : {ConditionFeature::Rms, ConditionFeature::MeanAbs, ConditionFeature::Peak}) {
    ASSERT_MATRIX_NEAR(compute_condition_feature(x, f), compute_condition_feature(kept, f), 0.0);
  }
  const Eigen::VectorXd empty = compute_condition_feature(Eigen::MatrixXd(0, 3), ConditionFeature::Rms);
  ASSERT_EQ(empty.size(), 3);
  EXPECT_TRUE(empty.array().isNaN().all());
}

TEST(ConditionFeatures, ShippedSliceMatchesNumpyStats) {
  // The derived table was computed independently with numpy from all 20,480 samples of each file.
  const causal::io::test::DerivedStats stats(
      causal::io::test::deploy_data("ims2-features/derived_per_file_stats_all984.csv"));
  const auto listing = causal::io::list_ims_directory(causal::io::test::deploy_data("ims2-slice"));
  ASSERT_EQ(listing.snapshots.size(), 6u);
  for (const auto& s : listing.snapshots) {
    const Eigen::MatrixXd x = causal::io::read_ims_snapshot(s.path, 4);
    const Eigen::Index r = stats.row(s.time_ns);
    ASSERT_GE(r, 0) << s.name;
    for (ConditionFeature f : kAll) {
      EXPECT_LT(causal::io::test::max_rel_err(compute_condition_feature(x, f), stats.at(f, r)), 1e-6)
          << s.name << " " << causal::io::to_string(f);
    }
  }
}

TEST(ConditionFeatures, SharedRawFilesMatchNumpyStats) {
  if (!causal::io::test::shared_available()) {
    GTEST_SKIP() << "full IMS data not found at " << causal::io::test::shared_ims2();
  }
  const std::string dir = causal::io::test::shared_ims2();
  const causal::io::test::DerivedStats stats(dir + "/derived_per_file_stats_all984.csv");
  const auto listing = causal::io::list_ims_directory(dir + "/raw");
  // Every 8th file of the 321 (about 40 files) keeps the runtime near a second; includes the last.
  double worst = 0.0;
  for (std::size_t i = 0; i < listing.snapshots.size(); i += (i + 8 < listing.snapshots.size() ? 8 : 1)) {
    const auto& s = listing.snapshots[i];
    const Eigen::MatrixXd x = causal::io::read_ims_snapshot(s.path, 4);
    const Eigen::Index r = stats.row(s.time_ns);
    ASSERT_GE(r, 0) << s.name;
    for (ConditionFeature f : kAll) {
      const double e = causal::io::test::max_rel_err(compute_condition_feature(x, f), stats.at(f, r));
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-6) << s.name << " " << causal::io::to_string(f);
    }
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", worst);
  RecordProperty("worst_relative_error", buf);
}
