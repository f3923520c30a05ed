// The robust-z reference detector on hand-computed data.
#include "robust_z_baseline.hpp"

#include <gtest/gtest.h>

namespace {

using causal::testing::RobustZParams;

TEST(RobustZBaseline, MedianMadAndFirstRunOfFive) {
  // Baseline rows 0..4 of channel 0: 1, 2, 3, 4, 100 -> median 3, |x - 3| = 2, 1, 0, 1, 97 -> MAD 1.
  // Threshold 6 x 1.4826 = 8.8956: 12 exceeds (z = 6.07), 11.8 does not (z = 5.94).
  Eigen::MatrixXd x(16, 2);
  x.col(0) << 1, 2, 3, 4, 100, 12, 12, 12, 12, 11.8, 12, 12, 12, 12, 12, 3;
  x.col(1) << 1, 2, 3, 4, 5, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3;
  RobustZParams p;
  p.baseline_begin = 0;
  p.baseline_end = 5;
  const auto r = causal::testing::robust_z_first_alarms(x, p);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_DOUBLE_EQ(r[0].median, 3.0);
  EXPECT_DOUBLE_EQ(r[0].scale, 1.4826);
  ASSERT_TRUE(r[0].first_alarm.has_value());
  EXPECT_EQ(*r[0].first_alarm, 14u);  // rows 5..8 are 4 in a row, row 9 breaks it, rows 10..14 are five
  EXPECT_FALSE(r[1].first_alarm.has_value());
}

TEST(RobustZBaseline, DropsAreAlarmsToo) {
  Eigen::MatrixXd x(12, 1);
  x.col(0) << 10, 11, 9, 10, 10, -5, -5, -5, -5, -5, 10, 10;
  x(3, 0) = 10.5;  // baseline 10, 11, 9, 10.5, 10 -> median 10, deviations 0, 1, 1, .5, 0 -> MAD .5
  RobustZParams p;
  p.baseline_begin = 0;
  p.baseline_end = 5;
  const auto r = causal::testing::robust_z_first_alarms(x, p);
  ASSERT_TRUE(r[0].first_alarm.has_value());
  EXPECT_EQ(*r[0].first_alarm, 9u);
}

TEST(RobustZBaseline, RefusesAConstantBaselineAndAWindowThatDoesNotFit) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Ones(10, 1);
  RobustZParams p;
  p.baseline_begin = 0;
  p.baseline_end = 5;
  EXPECT_THROW(causal::testing::robust_z_first_alarms(x, p), std::invalid_argument);
  p.baseline_end = 11;
  x(1, 0) = 2.0;
  EXPECT_THROW(causal::testing::robust_z_first_alarms(x, p), std::invalid_argument);
}

}  // namespace
