// causal::pipeline::StructuredFactorStream: on a calibration window it must learn the healthy centre (the
// window mean, computed here independently) and, for non-Gaussian noise, a causal order that puts every true
// cause before its effect; then it must report exactly what a plain FactorStream reports when fed the centred
// data with the learned restriction, from the first sample on (nothing lost to calibration), whatever the
// framing; failures fall back to the configured model with a stated problem.
#include "causal/pipeline/structured_factor_stream.hpp"

#include "matrix_asserts.hpp"
#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace causal::pipeline {
namespace {

constexpr int kG = 4;
constexpr std::int64_t kT0 = 1'700'000'000'000'000'000LL;
constexpr double kPeriod = 600e9;  // ten minutes, condition-level cadence

// True structural VAR(1):  y = B0 y + A1 y[n-1] + mu_shift + e, e uniform (non-Gaussian), unit variance.
// Instantaneous links (0-based): 2 -> 0 (0.7), 0 -> 1 (0.6), 2 -> 3 (0.5); a true order is 2, 0, 1, 3.
Eigen::MatrixXd true_b0() {
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(kG, kG);
  b(0, 2) = 0.7;
  b(1, 0) = 0.6;
  b(3, 2) = 0.5;
  return b;
}

RowMajorMatrix simulate(int n, std::uint64_t seed, const Eigen::VectorXd& level) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-std::sqrt(3.0), std::sqrt(3.0));
  Eigen::MatrixXd a1 = 0.3 * Eigen::MatrixXd::Identity(kG, kG);
  a1(0, 1) = 0.2;
  const Eigen::MatrixXd i_minus_b0 = Eigen::MatrixXd::Identity(kG, kG) - true_b0();
  RowMajorMatrix y(n, kG);
  Eigen::VectorXd prev = Eigen::VectorXd::Zero(kG);
  for (int t = -100; t < n; ++t) {  // burn-in
    Eigen::VectorXd e(kG);
    for (int k = 0; k < kG; ++k) e[k] = u(rng);
    const Eigen::VectorXd z = i_minus_b0.partialPivLu().solve(a1 * prev + e);
    prev = z;
    if (t >= 0) y.row(t) = (z + level).transpose();
  }
  return y;
}

FactorStreamParams params(bool self_lags = true, std::size_t publish_every = 5) {
  FactorStreamParams p;
  p.model.channels = kG;
  p.model.lag_order = 1;
  p.model.include_self_lags = self_lags;
  p.noise.automatic = false;
  p.noise.fixed = estimation::NoiseParams{1e-4, 1.0, 1.0};
  p.publish_every = publish_every;
  return p;
}

StructureSetting learning(std::size_t window, bool centre, bool order) {
  StructureSetting s;
  s.calibration_samples = window;
  s.centre = centre;
  s.learn_order = order;
  return s;
}

template <class Stream>
std::vector<FactorReport> feed_all(Stream& stream, const RowMajorMatrix& y, const std::vector<bool>& disc_rows) {
  std::vector<FactorReport> out;
  Eigen::Index at = 0;
  for (Eigen::Index s : causal::test::irregular_blocks(y.rows())) {
    const bool d = at == 0 || (!disc_rows.empty() && disc_rows[static_cast<std::size_t>(at)]);
    stream.feed(y.middleRows(at, s), static_cast<std::uint64_t>(at), d,
                kT0 + static_cast<std::int64_t>(static_cast<double>(at) * kPeriod), kPeriod, out);
    at += s;
  }
  stream.finish(out);
  return out;
}

void expect_same_reports(const std::vector<FactorReport>& got, const std::vector<FactorReport>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].sample_index, want[i].sample_index);
    EXPECT_EQ(got[i].time_ns, want[i].time_ns);
    EXPECT_EQ(got[i].outcome, want[i].outcome);
    EXPECT_MATRIX_NEAR(got[i].factors, want[i].factors, 1e-12);
    EXPECT_MATRIX_NEAR(got[i].std_devs, want[i].std_devs, 1e-12);
  }
}

Eigen::VectorXd levels() { return Eigen::Vector4d(-2.5, -2.3, -2.8, -3.0); }

TEST(StructuredFactorStream, WithoutLearningItIsThePlainFactorStream) {
  const RowMajorMatrix y = simulate(300, 1, levels());
  StructuredFactorStream structured(params(), StructureSetting{});
  FactorStream plain(params());
  expect_same_reports(feed_all(structured, y, {}), feed_all(plain, y, {}));
  EXPECT_TRUE(structured.structure().ready);
  EXPECT_EQ(structured.structure().centre.size(), 0);
  EXPECT_TRUE(structured.structure().order.empty());
  EXPECT_EQ(structured.structure().order_source, "") << "nothing learned, nothing configured: not assessed";
  EXPECT_TRUE(std::isnan(structured.structure().order_confidence));
}

TEST(StructuredFactorStream, CentresOnTheWindowMeanAndLosesNoSample) {
  const RowMajorMatrix y = simulate(400, 2, levels());
  std::vector<bool> disc(400, false);
  disc[77] = true;  // a gap inside the calibration window must reach the filter on replay
  disc[250] = true;
  StructuredFactorStream structured(params(), learning(120, true, false));
  const auto got = feed_all(structured, y, disc);

  Eigen::VectorXd mean = Eigen::VectorXd::Zero(kG);
  for (int i = 0; i < 120; ++i) mean += y.row(i).transpose();
  mean /= 120.0;
  EXPECT_MATRIX_NEAR(structured.structure().centre, mean, 1e-12);
  EXPECT_EQ(structured.structure().samples, 120u);

  const RowMajorMatrix centred = y.rowwise() - mean.transpose();
  FactorStream plain(params());
  expect_same_reports(got, feed_all(plain, centred, disc));
  EXPECT_EQ(got.size(), static_cast<std::size_t>(400 / 5 * kG));
  EXPECT_EQ(got.front().sample_index, 4u);
}

TEST(StructuredFactorStream, LearnsACausalOrderThatPutsEveryTrueCauseFirst) {
  const RowMajorMatrix y = simulate(1500, 3, levels());
  StructuredFactorStream structured(params(), learning(1000, true, true));
  const auto got = feed_all(structured, y, {});
  const auto& learned = structured.structure();
  ASSERT_TRUE(learned.problem.empty()) << learned.problem;
  ASSERT_EQ(learned.order.size(), static_cast<std::size_t>(kG));
  // The order's trust is assessed and published (analysis/order_trust.hpp).
  EXPECT_EQ(learned.order_source, "learned") << learned.order_summary;  // uniform noise, 1000 samples: identifiable
  EXPECT_GE(learned.order_confidence, 0.0);
  EXPECT_LE(learned.order_confidence, 1.0);
  EXPECT_FALSE(learned.order_summary.empty());
  ASSERT_EQ(learned.instantaneous_allowed.size(), static_cast<std::size_t>(kG));
  std::vector<int> position(kG);
  for (int p = 0; p < kG; ++p) position[static_cast<std::size_t>(learned.order[static_cast<std::size_t>(p)])] = p;
  const Eigen::MatrixXd b0 = true_b0();
  for (int k = 0; k < kG; ++k) {
    for (int j = 0; j < kG; ++j) {
      if (b0(k, j) == 0.0) continue;
      EXPECT_LT(position[static_cast<std::size_t>(j)], position[static_cast<std::size_t>(k)]) << j << " -> " << k;
      // The filter keeps the true link and drops its reverse.
      EXPECT_TRUE(learned.instantaneous_allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)]);
      EXPECT_FALSE(learned.instantaneous_allowed[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)]);
      EXPECT_NEAR(learned.b0(k, j), b0(k, j), 0.1) << j << " -> " << k;
    }
  }
  // The running layout is the restricted one: x01-style reverse factors are not in the state.
  const auto& layout = structured.stream()->layout();
  EXPECT_EQ(layout.total_factors(), 6 + 12 + 4);  // 6 ordered pairs at once, 12 cross lags, 4 self lags
  // Same reports as a plain FactorStream on the centred data with that restriction.
  FactorStreamParams restricted = params();
  restricted.model.instantaneous_allowed = learned.instantaneous_allowed;
  FactorStream plain(restricted);
  const RowMajorMatrix centred = y.rowwise() - learned.centre.transpose();
  expect_same_reports(got, feed_all(plain, centred, {}));
  // Truth check on the estimates: the last filter report of outcome 0 holds x13 (2 -> 0 at once) near 0.7.
  const int i13 = [&] {
    for (int i = 0; i < layout.factor_count(0); ++i)
      if (layout.factor_name(0, i) == "x13") return i;
    return -1;
  }();
  ASSERT_GE(i13, 0);
  const FactorReport& last0 = got[got.size() - kG];
  ASSERT_EQ(last0.outcome, 0);
  EXPECT_NEAR(last0.factors[i13], 0.7, 4.0 * last0.std_devs[i13] + 0.05);
}

TEST(StructuredFactorStream, AConfiguredGraphIsIntersectedWithTheLearnedOrder) {
  const RowMajorMatrix y = simulate(1200, 4, levels());
  FactorStreamParams p = params();
  // Configured: only 2 -> 0 and 0 -> 2 may exist at once; the order must keep 2 -> 0 and drop 0 -> 2.
  p.model.instantaneous_allowed.assign(kG, std::vector<bool>(kG, false));
  p.model.instantaneous_allowed[0][2] = true;
  p.model.instantaneous_allowed[2][0] = true;
  StructuredFactorStream structured(p, learning(1000, true, true));
  feed_all(structured, y, {});
  const auto& mask = structured.structure().instantaneous_allowed;
  ASSERT_TRUE(structured.structure().problem.empty()) << structured.structure().problem;
  ASSERT_EQ(mask.size(), static_cast<std::size_t>(kG));
  for (int k = 0; k < kG; ++k)
    for (int j = 0; j < kG; ++j)
      EXPECT_EQ(mask[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)], k == 0 && j == 2) << j << " -> " << k;
  // The plant's graph decides what the recommender may claim.
  EXPECT_EQ(structured.structure().order_source, "configured");
}

TEST(StructuredFactorStream, AFailedLearningFallsBackToTheConfiguredModelAndSaysWhy) {
  RowMajorMatrix y = simulate(300, 5, levels());
  y.col(3).head(100).setConstant(1.0);  // a dead channel in the window: LiNGAM cannot order it
  StructuredFactorStream structured(params(), learning(100, true, true));
  const auto got = feed_all(structured, y, {});
  const auto& learned = structured.structure();
  EXPECT_FALSE(learned.problem.empty());
  EXPECT_TRUE(learned.order.empty());
  EXPECT_TRUE(learned.instantaneous_allowed.empty());
  EXPECT_EQ(learned.centre.size(), kG);  // centring itself worked
  EXPECT_EQ(got.size(), static_cast<std::size_t>(300 / 5 * kG));
}

TEST(StructuredFactorStream, AStreamShorterThanTheWindowIsLearnedAtFinish) {
  const RowMajorMatrix y = simulate(60, 6, levels());
  StructuredFactorStream structured(params(), learning(200, true, false));
  const auto got = feed_all(structured, y, {});
  EXPECT_EQ(structured.structure().samples, 60u);
  EXPECT_EQ(got.size(), static_cast<std::size_t>(60 / 5 * kG));
}

TEST(StructuredFactorStream, NonFiniteSamplesDoNotPoisonTheCentre) {
  RowMajorMatrix y = simulate(200, 7, levels());
  y(10, 1) = std::numeric_limits<double>::quiet_NaN();
  StructuredFactorStream structured(params(), learning(100, true, false));
  feed_all(structured, y, {});
  double sum = 0.0;
  for (int i = 0; i < 100; ++i)
    if (i != 10) sum += y(i, 1);
  EXPECT_NEAR(structured.structure().centre[1], sum / 99.0, 1e-12);
  EXPECT_EQ(structured.stream()->counters().rejected_non_finite, 1u);
}

TEST(StructuredFactorStream, InvalidSettingsAreRejectedUpFront) {
  EXPECT_THROW(StructuredFactorStream(params(), learning(0, true, false)), std::invalid_argument);
  // Below one block of two channels, 10 x 2 x (M + 1) = 40, the order cannot be learned at all.
  EXPECT_THROW(StructuredFactorStream(params(), learning(39, false, true)), std::invalid_argument);
  // 40..79 (< 10 G (M + 1) = 80 for the 4 channels): the order is learned per block (two blocks of 2).
  const StructuredFactorStream blocked(params(), learning(79, false, true));
  EXPECT_EQ(blocked.structure().blocks, (std::vector<std::vector<int>>{{0, 1}, {2, 3}}));
  const StructuredFactorStream dense(params(), learning(80, false, true));
  EXPECT_EQ(dense.structure().blocks, (std::vector<std::vector<int>>{{0, 1, 2, 3}}));
  StructureSetting negative = learning(100, false, true);
  negative.prune_threshold = -0.1;
  EXPECT_THROW(StructuredFactorStream(params(), negative), std::invalid_argument);
  FactorStreamParams bad = params();
  bad.publish_every = 0;
  EXPECT_THROW(StructuredFactorStream(bad, learning(100, true, false)), std::invalid_argument);
}

}  // namespace

}  // namespace causal::pipeline
