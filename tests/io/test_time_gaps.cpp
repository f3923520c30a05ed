// causal::io::find_time_gaps on hand-built time axes.
#include "causal/io/time_gaps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace {

constexpr std::int64_t kMin = 60LL * 1000000000LL;

std::vector<std::int64_t> axis(const std::vector<std::int64_t>& minutes) {
  std::vector<std::int64_t> t;
  for (auto m : minutes) t.push_back(m * kMin);
  return t;
}

TEST(TimeGaps, LongerThanFactorTimesTheMedianIntervalIsAGap) {
  // Intervals 10, 10, 10, 30 (missed snapshots: exactly 3x, not a gap), 10, 31 (gap), 10, 2880 (two days).
  const auto t = axis({0, 10, 20, 30, 60, 70, 101, 111, 2991});
  const auto g = causal::io::find_time_gaps(t, 3.0);
  EXPECT_EQ(g.median_interval_ns, 10 * kMin);
  EXPECT_EQ(g.rows, (std::vector<std::size_t>{6, 8}));
}

TEST(TimeGaps, RegularAxisHasNoneAndShortOnesNeither) {
  EXPECT_TRUE(causal::io::find_time_gaps(axis({0, 10, 20, 30}), 3.0).rows.empty());
  EXPECT_TRUE(causal::io::find_time_gaps(axis({5}), 3.0).rows.empty());
  EXPECT_EQ(causal::io::find_time_gaps(axis({5}), 3.0).median_interval_ns, 0);
  EXPECT_TRUE(causal::io::find_time_gaps({}, 3.0).rows.empty());
}

TEST(TimeGaps, TheFactorIsHonouredAndChecked) {
  const auto t = axis({0, 10, 20, 45, 55});  // a 25-minute interval: a gap at 2x, not at 3x
  EXPECT_EQ(causal::io::find_time_gaps(t, 2.0).rows, (std::vector<std::size_t>{3}));
  EXPECT_TRUE(causal::io::find_time_gaps(t, 3.0).rows.empty());
  EXPECT_THROW(causal::io::find_time_gaps(t, 0.5), std::invalid_argument);
  EXPECT_THROW(causal::io::find_time_gaps(t, std::nan("")), std::invalid_argument);
}

}  // namespace
