// The robustness variant generator against its construction: every property is checked on the produced table
// against the base table (independent truth), not against stored numbers of the generator itself.
#include "ims_variants.hpp"

#include "causal/io/feature_table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

namespace {

using causal::testing::BaseRun;
using causal::testing::Variant;

constexpr std::int64_t kTenMinutes = 600LL * 1000000000LL;

const BaseRun& base() {
  static const BaseRun b =
      causal::testing::read_base_run(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  return b;
}

TEST(ImsVariants, BaseIsTestTwo) {
  ASSERT_EQ(base().values.rows(), 984);
  ASSERT_EQ(base().values.cols(), 4);
  EXPECT_EQ(base().channel_names.front(), "Bearing 1");
  for (std::size_t i = 1; i < base().time_ns.size(); ++i) ASSERT_EQ(base().time_ns[i] - base().time_ns[i - 1], kTenMinutes);
}

TEST(ImsVariants, GapsAreLongAndFollowedByLevelShiftsOfEveryChannel) {
  const Variant v = causal::testing::make_gaps_variant(base(), 7);
  ASSERT_EQ(v.values.rows(), base().values.rows());
  std::vector<std::size_t> gap_rows;
  for (std::size_t i = 1; i < v.time_ns.size(); ++i) {
    const std::int64_t d = v.time_ns[i] - v.time_ns[i - 1];
    if (d != kTenMinutes) {
      gap_rows.push_back(i);
      EXPECT_GE(d, 4 * 3600LL * 1000000000LL) << "row " << i;  // hours at least
    }
  }
  ASSERT_EQ(gap_rows.size(), 3u);
  EXPECT_GE(v.time_ns[gap_rows[1]] - v.time_ns[gap_rows[1] - 1], 6 * 24 * 3600LL * 1000000000LL);  // a 6-day stop
  EXPECT_LE(gap_rows.back() + 140, v.healthy_end);  // room to re-learn before the degradation
  for (Eigen::Index c = 0; c < v.values.cols(); ++c) {
    double expected = 1.0;
    std::size_t segment = 0;
    for (std::size_t i = 0; i < v.time_ns.size(); ++i) {
      if (segment < gap_rows.size() && i == gap_rows[segment]) {
        const double step = v.values(static_cast<Eigen::Index>(i), c) / base().values(static_cast<Eigen::Index>(i), c) / expected;
        EXPECT_GE(step, 1.15 - 1e-12);
        EXPECT_LE(step, 1.20 + 1e-12);
        expected *= step;
        ++segment;
      }
      ASSERT_NEAR(v.values(static_cast<Eigen::Index>(i), c), expected * base().values(static_cast<Eigen::Index>(i), c),
                  1e-12 * std::abs(v.values(static_cast<Eigen::Index>(i), c)));
    }
  }
}

TEST(ImsVariants, StepsHitTwoHealthyChannelsInTheFirstHalfAndStay) {
  const Variant v = causal::testing::make_steps_variant(base(), 7);
  std::set<int> stepped;
  for (Eigen::Index c = 0; c < v.values.cols(); ++c) {
    const Eigen::ArrayXd ratio = v.values.col(c).array() / base().values.col(c).array();
    Eigen::Index first = -1;
    for (Eigen::Index i = 0; i < ratio.size(); ++i) {
      if (ratio[i] != 1.0) {
        first = i;
        break;
      }
    }
    if (first < 0) continue;
    stepped.insert(static_cast<int>(c));
    EXPECT_LT(first, 492) << "step in the first half";
    EXPECT_GE(ratio[first], 1.20);
    EXPECT_LE(ratio[first], 1.40);
    EXPECT_LT((ratio.tail(ratio.size() - first) - ratio[first]).abs().maxCoeff(), 1e-12) << "the step stays";
  }
  EXPECT_EQ(stepped.size(), 2u);
  EXPECT_EQ(stepped.count(base().failing_channel), 0u);
}

TEST(ImsVariants, EightChannelsAreTwoSensorsPerBearing) {
  const Variant v = causal::testing::make_eight_channel_variant(base(), 7);
  ASSERT_EQ(v.values.cols(), 8);
  EXPECT_EQ(v.channel_names[0], "Bearing 1 C1");
  EXPECT_EQ(v.channel_names[1], "Bearing 1 C2");
  EXPECT_EQ(v.channel_names[7], "Bearing 4 C2");
  EXPECT_EQ(v.failing_channels, (std::vector<int>{0, 1}));
  for (Eigen::Index b = 0; b < 4; ++b) {
    EXPECT_EQ(v.values.col(2 * b), base().values.col(b));
    const Eigen::ArrayXd log_ratio = (v.values.col(2 * b + 1).array() / base().values.col(b).array()).log();
    const double mean = log_ratio.mean();
    const double sd = std::sqrt((log_ratio - mean).square().sum() / static_cast<double>(log_ratio.size() - 1));
    EXPECT_NEAR(mean, 0.0, 4.0 * 0.01 / std::sqrt(984.0));  // 4 standard errors
    EXPECT_NEAR(sd, 0.01, 0.001);                           // ~4.4 standard errors of a 984-sample sd
  }
}

TEST(ImsVariants, StretchedRunIsContinuousAndEndsWithTheDegradation) {
  const Variant v = causal::testing::make_stretched_variant(base(), 7, 6000);
  ASSERT_EQ(v.values.rows(), 6000);
  const std::size_t tail = 984 - base().healthy_end;
  EXPECT_EQ(v.healthy_end, 6000 - tail);
  for (std::size_t i = 1; i < v.time_ns.size(); ++i) ASSERT_EQ(v.time_ns[i] - v.time_ns[i - 1], kTenMinutes);
  for (std::size_t i = 0; i < v.source_row.size(); ++i) {
    if (i > 0) {
      const auto step = static_cast<long long>(v.source_row[i]) - static_cast<long long>(v.source_row[i - 1]);
      ASSERT_LE(std::llabs(step), 1) << "row " << i << " does not continue the previous level";
    }
    const bool healthy_source = v.source_row[i] < base().healthy_end;
    ASSERT_EQ(healthy_source, i < v.healthy_end) << "row " << i;
    const double ratio = v.values(static_cast<Eigen::Index>(i), 0) / base().values(static_cast<Eigen::Index>(v.source_row[i]), 0);
    ASSERT_LT(std::abs(std::log(ratio)), 6 * 0.005) << "row " << i;
  }
  // The first healthy stretch and the degrading end are the base rows themselves.
  EXPECT_EQ(v.values.topRows(base().healthy_end), base().values.topRows(base().healthy_end));
  EXPECT_EQ(v.values.bottomRows(static_cast<Eigen::Index>(tail)), base().values.bottomRows(static_cast<Eigen::Index>(tail)));
}

TEST(ImsVariants, SameSeedSameVariantOtherSeedOther) {
  const auto a = causal::testing::make_all_variants(base(), 7);
  const auto b = causal::testing::make_all_variants(base(), 7);
  const auto c = causal::testing::make_all_variants(base(), 8);
  ASSERT_EQ(a.size(), 5u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].values, b[i].values) << a[i].name;
    EXPECT_EQ(a[i].time_ns, b[i].time_ns) << a[i].name;
    if (a[i].name != "unchanged") {
      EXPECT_NE(a[i].values, c[i].values) << a[i].name;
    }
  }
  EXPECT_EQ(a.back().values, base().values);
}

TEST(ImsVariants, CsvReadsBackAsAnImsMergedTable) {
  const Variant v = causal::testing::make_eight_channel_variant(base(), 7);
  const std::string path = (std::filesystem::temp_directory_path() / "ims_variants_roundtrip.csv").string();
  causal::testing::write_variant_csv(v, path);
  const causal::io::FeatureTable t = causal::io::read_feature_table(path);
  std::remove(path.c_str());
  EXPECT_EQ(t.channel_names, v.channel_names);
  EXPECT_EQ(t.time_ns, v.time_ns);
  EXPECT_EQ(t.values, v.values);  // 17 significant digits round-trip exactly
}

}  // namespace
