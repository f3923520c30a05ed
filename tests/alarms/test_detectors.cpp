// ClippedCusum, WindowMean and PersistenceLatch against direct reference computations, and their
// checkpoints against the uninterrupted detector.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "causal/alarms/detectors.hpp"
#include "causal/estimation/state_archive.hpp"

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

// ---- checkpoints: save mid-stream, restore into a default-constructed object (other settings), continue:
// every value must equal the uninterrupted detector's, bit for bit.
namespace {
template <typename D>
D restored_copy(const D& d) {
  causal::estimation::StateWriter w;
  d.save(w);
  causal::estimation::StateReader r(w.bytes());
  D out;
  out.restore(r);
  EXPECT_TRUE(r.at_end());
  return out;
}
}  // namespace

TEST(DetectorCheckpoint, CusumWindowLatchContinueAsUninterrupted) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.5, 2.0);
  ClippedCusum c(1.0, 3.0, 7.0), c2;
  WindowMean w(7), w2;
  PersistenceLatch l(2, 3), l2;
  for (int i = 0; i < 3000; ++i) {
    if (i % 250 == 123) {  // cut at varied phases of the window and of excursions
      c2 = restored_copy(c);
      w2 = restored_copy(w);
      l2 = restored_copy(l);
    }
    const double z = n(rng);
    const auto ti = static_cast<std::uint64_t>(i);
    c.update(z, ti, 1000 * i);
    w.push(z * z);
    const auto tr = l.update(c.value(), 4.0, 2.0);
    if (i < 123) continue;  // the copies exist from the first cut on
    c2.update(z, ti, 1000 * i);
    w2.push(z * z);
    ASSERT_EQ(l2.update(c2.value(), 4.0, 2.0), tr) << i;
    ASSERT_EQ(c2.value(), c.value()) << i;
    ASSERT_EQ(c2.onset_index(), c.onset_index()) << i;
    ASSERT_EQ(c2.onset_time_ns(), c.onset_time_ns()) << i;
    ASSERT_EQ(w2.mean(), w.mean()) << i;
    ASSERT_EQ(w2.median(), w.median()) << i;
    ASSERT_EQ(w2.count(), w.count()) << i;
    ASSERT_EQ(l2.active(), l.active()) << i;
    ASSERT_EQ(l2.above_count(), l.above_count()) << i;
    ASSERT_EQ(l2.below_count(), l.below_count()) << i;
  }
}

TEST(DetectorCheckpoint, ForeignOrInconsistentSectionsAreRefused) {
  causal::estimation::StateWriter w;
  WindowMean(4).save(w);
  causal::estimation::StateReader r(w.bytes());
  ClippedCusum c;
  EXPECT_THROW(c.restore(r), causal::estimation::StateError);  // a window where a CUSUM is expected

  causal::estimation::StateWriter bad;  // a window whose write position lies outside its buffer
  bad.begin("window_mean", 1);
  bad.put(std::vector<double>(4, 0.0));
  bad.put(4);
  bad.put(4);
  bad.put(0.0);
  causal::estimation::StateReader rb(bad.bytes());
  WindowMean m;
  EXPECT_THROW(m.restore(rb), causal::estimation::StateError);
}
