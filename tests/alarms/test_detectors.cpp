// ClippedCusum, WindowMean and PersistenceLatch against direct reference computations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "causal/alarms/detectors.hpp"

using namespace causal::alarms;

TEST(ClippedCusum, MatchesReferenceRecursion) {
  const double k = 1.0, clip = 3.0, cap = 7.0;
  ClippedCusum c(k, clip, cap);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.8, 2.0);
  double ref = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double z = n(rng);
    ref = std::min(cap, std::max(0.0, ref + std::min(z, clip) - k));
    ASSERT_NEAR(c.update(z, static_cast<std::uint64_t>(i), i * 10), ref, 1e-12) << "step " << i;
  }
}

TEST(ClippedCusum, SingleHugeSpikeAddsAtMostClipMinusK) {
  ClippedCusum c(1.5, 4.0, 100.0);
  EXPECT_DOUBLE_EQ(c.update(1e9, 0, 0), 2.5);
  EXPECT_DOUBLE_EQ(c.update(0.0, 1, 0), 1.0);
  EXPECT_DOUBLE_EQ(c.update(0.0, 2, 0), 0.0);
  EXPECT_FALSE(c.in_excursion());
}

TEST(ClippedCusum, OnsetIsFirstObservationOfExcursionAndNaNIsIgnored) {
  ClippedCusum c(0.5, 4.0, 50.0);
  for (std::uint64_t i = 0; i < 10; ++i) c.update(0.0, i, static_cast<std::int64_t>(i) * 100);
  c.update(2.0, 10, 1000);  // excursion starts here
  c.update(std::nan(""), 11, 1100);
  c.update(2.0, 12, 1200);
  EXPECT_TRUE(c.in_excursion());
  EXPECT_EQ(c.onset_index(), 10u);
  EXPECT_EQ(c.onset_time_ns(), 1000);
  EXPECT_DOUBLE_EQ(c.value(), 3.0);
}

TEST(ClippedCusum, RejectsBadDesign) {
  EXPECT_THROW(ClippedCusum(0.0, 4.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ClippedCusum(2.0, 1.0, 1.0), std::invalid_argument);
}

TEST(WindowMean, SlidingMeanAndMedianMatchReference) {
  WindowMean w(5);
  std::vector<double> all;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int i = 0; i < 200; ++i) {
    const double v = u(rng);
    all.push_back(v);
    w.push(v);
    const std::size_t from = all.size() > 5 ? all.size() - 5 : 0;
    std::vector<double> last(all.begin() + static_cast<std::ptrdiff_t>(from), all.end());
    double mean = 0;
    for (double x : last) mean += x;
    mean /= static_cast<double>(last.size());
    ASSERT_NEAR(w.mean(), mean, 1e-12);
    std::sort(last.begin(), last.end());
    const double med = last.size() % 2 ? last[last.size() / 2] : 0.5 * (last[last.size() / 2 - 1] + last[last.size() / 2]);
    ASSERT_DOUBLE_EQ(w.median(), med);
  }
  w.push(std::nan(""));
  EXPECT_EQ(w.count(), 5);
}

TEST(PersistenceLatch, RaisesAfterConsecutiveAndClearsAfterConsecutive) {
  PersistenceLatch l(2, 3);
  using T = PersistenceLatch::Transition;
  EXPECT_EQ(l.update(5, 4, 2), T::None);   // 1 above
  EXPECT_EQ(l.update(1, 4, 2), T::None);   // run broken
  EXPECT_EQ(l.update(5, 4, 2), T::None);
  EXPECT_EQ(l.update(std::nan(""), 4, 2), T::None);  // missing: neither advances nor resets
  EXPECT_EQ(l.update(5, 4, 2), T::Raise);
  EXPECT_TRUE(l.active());
  EXPECT_EQ(l.update(3, 4, 2), T::None);   // between clear and raise: hysteresis band, stays active
  EXPECT_EQ(l.update(1, 4, 2), T::None);
  EXPECT_EQ(l.update(1, 4, 2), T::None);
  EXPECT_EQ(l.update(3, 4, 2), T::None);   // resets the clear count
  EXPECT_EQ(l.update(1, 4, 2), T::None);
  EXPECT_EQ(l.update(1, 4, 2), T::None);
  EXPECT_EQ(l.update(1, 4, 2), T::Clear);
  EXPECT_FALSE(l.active());
}
