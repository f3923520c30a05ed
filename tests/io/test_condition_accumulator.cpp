#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>

#include "causal/io/condition_features.hpp"
#include "causal/io/ims_directory.hpp"
#include "causal/estimation/state_archive.hpp"
#include "io_test_util.hpp"
#include "matrix_asserts.hpp"
#include "real_stats.hpp"

using causal::io::compute_condition_feature;
using causal::io::ConditionAccumulator;
using causal::io::ConditionFeature;

namespace {

const ConditionFeature kAll[] = {ConditionFeature::Rms, ConditionFeature::MeanAbs, ConditionFeature::Kurtosis,
                                 ConditionFeature::Peak};
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Feeds x (N x G) in blocks whose sizes come from `sizes` (cycled).
void feed(ConditionAccumulator& acc, const Eigen::MatrixXd& x, const std::vector<std::size_t>& sizes) {
  const RowMajor rm = x;
  std::size_t done = 0, k = 0;
  const auto n = static_cast<std::size_t>(x.rows());
  while (done < n) {
    const std::size_t b = std::min(sizes[k++ % sizes.size()], n - done);
    acc.add(rm.data() + done * static_cast<std::size_t>(x.cols()), b);
    done += b;
  }
}

void expect_rel_near(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double rel, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a(i), b(i), rel * std::abs(b(i))) << what << " [" << i << "]";
  }
}

}  // namespace

TEST(ConditionAccumulator, RejectsBadChannelCount) {
  EXPECT_THROW(ConditionAccumulator(0), std::invalid_argument);
  EXPECT_THROW(ConditionAccumulator(-3), std::invalid_argument);
}

TEST(ConditionAccumulator, StreamingEqualsBatchForAnyBlocking) {
  std::mt19937_64 rng(11);
  std::student_t_distribution<double> heavy(4.0);
  Eigen::MatrixXd x(20480, 4);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    x(i, 0) = 0.1 * heavy(rng);
    x(i, 1) = 50.0 + heavy(rng);  // offset: exercises the mean-shift terms of the merge
    x(i, 2) = std::sin(0.01 * static_cast<double>(i)) + 0.01 * heavy(rng);
    x(i, 3) = -2.0 + 1e-3 * heavy(rng);
  }
  const std::vector<std::vector<std::size_t>> blockings = {
      {20480}, {1}, {2048}, {1000}, {1, 7, 300, 2, 4096}, {5000, 1, 1}};
  for (const auto& sizes : blockings) {
    ConditionAccumulator acc(4);
    feed(acc, x, sizes);
    EXPECT_EQ(acc.count(), 20480u);
    EXPECT_EQ(acc.rejected(), 0u);
    for (ConditionFeature f : kAll) {
      expect_rel_near(acc.value(f), compute_condition_feature(x, f), 1e-11,
                      causal::io::to_string(f) + " first block " + std::to_string(sizes[0]));
    }
  }
}

TEST(ConditionAccumulator, ClosedFormsSquareWaveAndConstant) {
  ConditionAccumulator acc(2);
  for (int i = 0; i < 1001; ++i) {
    const double row[2] = {(i % 2 == 0) ? 1.0 : -1.0, 0.3};
    acc.add(row, 1);
  }
  // 1001 samples of +-1: mean = 1/1001, so kurtosis = m4/m2^2 with m2 = 1 - mu^2, computed exactly.
  const double mu = 1.0 / 1001.0;
  const double m2 = 1.0 - mu * mu;
  const double m4 = (501.0 * std::pow(1 - mu, 4) + 500.0 * std::pow(1 + mu, 4)) / 1001.0;
  EXPECT_NEAR(acc.value(ConditionFeature::Kurtosis)(0), m4 / (m2 * m2), 1e-13);
  EXPECT_NEAR(acc.value(ConditionFeature::Rms)(0), 1.0, 1e-15);
  EXPECT_NEAR(acc.value(ConditionFeature::Rms)(1), 0.3, 1e-15);
  EXPECT_NEAR(acc.value(ConditionFeature::MeanAbs)(1), 0.3, 1e-15);
  EXPECT_EQ(acc.value(ConditionFeature::Peak)(1), 0.3);
  EXPECT_TRUE(std::isnan(acc.value(ConditionFeature::Kurtosis)(1)));
}

TEST(ConditionAccumulator, NonFiniteRowsRejectedAndCounted) {
  ConditionAccumulator acc(2);
  const double rows[] = {1, 2, NAN, 5, -1, 4, 3, INFINITY, 2, -2};
  acc.add(rows, 5);
  EXPECT_EQ(acc.count(), 3u);
  EXPECT_EQ(acc.rejected(), 2u);
  Eigen::MatrixXd kept(3, 2);
  kept << 1, 2, -1, 4, 2, -2;
  for (ConditionFeature f : kAll) {
    expect_rel_near(acc.value(f), compute_condition_feature(kept, f), 1e-14, causal::io::to_string(f));
  }
}

TEST(ConditionAccumulator, EmptyIsNanAndResetClears) {
  ConditionAccumulator acc(3);
  EXPECT_TRUE(acc.value(ConditionFeature::Rms).array().isNaN().all());
  const double rows[] = {1, 2, 3, 4, 5, 6};
  acc.add(rows, 2);
  acc.add(nullptr, 0);  // no-op
  EXPECT_EQ(acc.count(), 2u);
  acc.reset();
  EXPECT_EQ(acc.count(), 0u);
  EXPECT_EQ(acc.rejected(), 0u);
  EXPECT_TRUE(acc.value(ConditionFeature::Peak).array().isNaN().all());
  const double other[] = {-7, 0, 1};
  acc.add(other, 1);
  EXPECT_EQ(acc.value(ConditionFeature::Peak)(0), 7.0);  // nothing left over from before the reset
  EXPECT_EQ(acc.value(ConditionFeature::Peak)(2), 1.0);
}

TEST(ConditionAccumulator, ShippedSliceStreamedMatchesNumpyStats) {
  // Streams each shipped snapshot in 2048-sample frames, as the replay service does, and compares with
  // the independent numpy statistics.
  const causal::io::test::DerivedStats stats(
      causal::io::test::deploy_data("ims2-features/derived_per_file_stats_all984.csv"));
  const auto listing = causal::io::list_ims_directory(causal::io::test::deploy_data("ims2-slice"));
  ASSERT_EQ(listing.snapshots.size(), 6u);
  ConditionAccumulator acc(4);
  for (const auto& s : listing.snapshots) {
    const Eigen::MatrixXd x = causal::io::read_ims_snapshot(s.path, 4);
    acc.reset();
    feed(acc, x, {2048});
    ASSERT_EQ(acc.count(), 20480u);
    const Eigen::Index r = stats.row(s.time_ns);
    ASSERT_GE(r, 0) << s.name;
    for (ConditionFeature f : kAll) {
      EXPECT_LT(causal::io::test::max_rel_err(acc.value(f), stats.at(f, r)), 1e-6)
          << s.name << " " << causal::io::to_string(f);
    }
  }
}

// Checkpoint: a window cut by a restart (save, restore into a fresh accumulator, add the rest) gives the
// same features bit for bit as the uninterrupted window fed in the same blocks; rejected rows are kept.
TEST(ConditionAccumulator, CheckpointContinuesTheWindowBitForBit) {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> normal(0.0, 1.0);
  RowMajor x(1000, 3);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = 0.3 + normal(rng);
  x(10, 1) = std::numeric_limits<double>::quiet_NaN();
  ConditionAccumulator whole(3), first(3);
  whole.add(x.data(), 400);
  whole.add(x.data() + 400 * 3, 600);
  first.add(x.data(), 400);
  causal::estimation::StateWriter w;
  first.save(w);
  ConditionAccumulator restored(3);
  causal::estimation::StateReader r(w.bytes());
  restored.restore(r);
  EXPECT_TRUE(r.at_end());
  restored.add(x.data() + 400 * 3, 600);
  EXPECT_EQ(restored.count(), whole.count());
  EXPECT_EQ(restored.rejected(), 1u);
  for (ConditionFeature f : kAll) {
    const Eigen::VectorXd a = restored.value(f), b = whole.value(f);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * 3), 0) << causal::io::to_string(f);
  }
  ConditionAccumulator four(4);
  causal::estimation::StateReader r4(w.bytes());
  EXPECT_THROW(four.restore(r4), causal::estimation::StateError);
  causal::estimation::StateReader cut(w.bytes().substr(0, w.bytes().size() - 1));
  EXPECT_THROW(restored.restore(cut), causal::estimation::StateError);
}

// The channels of an all-finite block run side by side straight from the row-major block; a block with a
// non-finite row is gathered channel-major and run one channel at a time. Both give the same running sums bit
// for bit (the whole saved state: moments, compensated |x| sums, peaks): the fast accumulator gets each block
// and then its non-finite row alone, the other the block with that row appended (so it takes the gather path).
TEST(ConditionAccumulator, ChannelsSideBySideEqualOneChannelAtATimeBitForBit) {
  std::mt19937_64 rng(23);
  std::student_t_distribution<double> heavy(3.0);
  for (const int g : {1, 2, 3, 4, 5, 7, 8, 9}) {
    ConditionAccumulator side_by_side(g), one_at_a_time(g);
    std::size_t fed = 0;
    for (const std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{1024}, std::size_t{333}, std::size_t{4096}}) {
      RowMajor block(static_cast<Eigen::Index>(n) + 1, g);
      for (Eigen::Index i = 0; i < block.rows(); ++i) {
        for (int c = 0; c < g; ++c) block(i, c) = 10.0 * c - 3.0 + std::pow(10.0, c % 3 - 1) * heavy(rng);
      }
      block(block.rows() - 1, g / 2) = std::numeric_limits<double>::infinity();
      side_by_side.add(block.data(), n);
      side_by_side.add(block.data() + n * static_cast<std::size_t>(g), 1);
      one_at_a_time.add(block.data(), n + 1);
      fed += n;
    }
    ASSERT_EQ(side_by_side.count(), fed) << g;
    ASSERT_EQ(one_at_a_time.count(), fed) << g;
    ASSERT_EQ(one_at_a_time.rejected(), 5u) << g;
    causal::estimation::StateWriter a, b;
    side_by_side.save(a);
    one_at_a_time.save(b);
    EXPECT_EQ(a.bytes(), b.bytes()) << g << " channels";
  }
}
