// SvarKalmanFilter: hand-computed steps, split == dense stacked filter, gaps / non-finite handling, long-run SPD.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <tuple>

#include "causal/estimation/batch_estimation.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"
#include "matrix_asserts.hpp"
#include "svar_test_support.hpp"

namespace causal {
namespace {

using test::kNaN;
using test::spec_g;

// The filter stepped over sim.y against the dense stacked reference: every filtered estimate, then the covariance
// of the last outcome (`last`, `d` factors) after the last sample.
void expect_filter_matches_dense(const estimation::SvarLayout& layout, const std::vector<estimation::NoiseParams>& noise,
                                 const test::Simulation& sim, const test::DenseReference& ref, int last, int d) {
  estimation::SvarKalmanFilter filter(layout, noise);
  Eigen::VectorXd x(layout.total_factors());
  const int samples = static_cast<int>(sim.y.rows());
  for (int n = 0; n < samples; ++n) {
    const Eigen::RowVectorXd row = sim.y.row(n);
    filter.step(row.data());
    filter.estimates(x.data());
    ASSERT_MATRIX_NEAR(x, ref.x_filt[n], 1e-10);
  }
  ASSERT_MATRIX_NEAR(filter.covariance(last), ref.p_filt[samples - 1].bottomRightCorner(d, d), 1e-10);
}

// G = 2, M = 1: outcome 1 has factors (x12, xL12) with h = (y2[n], y2[n-1]); outcome 2 has (x21, xL21) with
// h = (y1[n], y1[n-1]). q = 0.5, r = 1, p0 = 1. Data y[0] = (0, 1), y[1] = (1, 1), y[2] = (2, 0).
//
// n = 0: first sample, no prediction (P = I), warm-up (M = 1): x = 0, P = I.
// n = 1: predict P = 1.5 I.
//   outcome 1: h = (1, 1); u = P h = (1.5, 1.5); S = h.u + r = 3 + 1 = 4; e = y1[1] - h.x = 1;
//              K = u / S = (0.375, 0.375); x = K e = (0.375, 0.375);
//              P = P - u u^T / S = [[1.5 - 0.5625, -0.5625], [-0.5625, 1.5 - 0.5625]] = [[0.9375, -0.5625], ...]
//   outcome 2: h = (y1[1], y1[0]) = (1, 0); u = (1.5, 0); S = 2.5; e = y2[1] - 0 = 1; K = (0.6, 0);
//              x = (0.6, 0); P = [[1.5 - 2.25 / 2.5, 0], [0, 1.5]] = [[0.6, 0], [0, 1.5]]
// n = 2: predict P += 0.5 I.
//   outcome 1: P = [[23/16, -9/16], [-9/16, 23/16]]; h = (y2[2], y2[1]) = (0, 1); u = P h = (-9/16, 23/16);
//              S = 23/16 + 1 = 39/16; e = 2 - (0 * 0.375 + 1 * 0.375) = 13/8;
//              K = u / S = (-9/39, 23/39) = (-3/13, 23/39); x = (3/8 - (3/13)(13/8), 3/8 + (23/39)(13/8))
//                = (0, 3/8 + 23/24) = (0, 4/3);
//              P = P - u u^T / S: P11 = 23/16 - 81/624 = 816/624 = 17/13, P12 = -9/16 + 207/624 = -144/624 = -3/13,
//              P22 = 23/16 - 529/624 = 368/624 = 23/39.
//   outcome 2: P = [[1.1, 0], [0, 2.0]]; h = (y1[2], y1[1]) = (2, 1); u = (2.2, 2.0); S = 4.4 + 2 + 1 = 7.4;
//              e = 0 - (2 * 0.6 + 0) = -1.2; K = (2.2, 2) / 7.4 = (11/37, 10/37);
//              x = (0.6 - 1.2 * 11/37, -1.2 * 10/37) = (9/37, -12/37);
//              P11 = 1.1 - 4.84 / 7.4 = 33/74, P12 = -4.4 / 7.4 = -22/37, P22 = 2 - 4 / 7.4 = 54/37.
TEST(SvarKalmanFilter, HandComputedTwoSteps) {
  estimation::SvarLayout layout(spec_g(2, 1));
  estimation::SvarKalmanFilter filter(layout, {estimation::NoiseParams{0.5, 1.0, 1.0}});
  const double y0[] = {0.0, 1.0}, y1[] = {1.0, 1.0}, y2[] = {2.0, 0.0};

  EXPECT_EQ(filter.step(y0), estimation::SampleStatus::WarmUp);
  ASSERT_MATRIX_NEAR(filter.covariance(0), Eigen::Matrix2d::Identity(), 0.0);

  EXPECT_EQ(filter.step(y1), estimation::SampleStatus::Updated);
  EXPECT_NEAR(filter.last_innovation(0), 1.0, 1e-15);
  EXPECT_NEAR(filter.last_innovation_variance(0), 4.0, 1e-15);
  ASSERT_MATRIX_NEAR(filter.estimate(0), Eigen::Vector2d(0.375, 0.375), 1e-15);
  Eigen::Matrix2d p1;
  p1 << 0.9375, -0.5625, -0.5625, 0.9375;
  ASSERT_MATRIX_NEAR(filter.covariance(0), p1, 1e-15);
  EXPECT_NEAR(filter.last_innovation_variance(1), 2.5, 1e-15);
  ASSERT_MATRIX_NEAR(filter.estimate(1), Eigen::Vector2d(0.6, 0.0), 1e-15);
  ASSERT_MATRIX_NEAR(filter.covariance(1), Eigen::Vector2d(0.6, 1.5).asDiagonal().toDenseMatrix(), 1e-15);

  EXPECT_EQ(filter.step(y2), estimation::SampleStatus::Updated);
  EXPECT_NEAR(filter.last_innovation(0), 13.0 / 8.0, 1e-14);
  EXPECT_NEAR(filter.last_innovation_variance(0), 39.0 / 16.0, 1e-14);
  ASSERT_MATRIX_NEAR(filter.estimate(0), Eigen::Vector2d(0.0, 4.0 / 3.0), 1e-14);
  Eigen::Matrix2d p2;
  p2 << 17.0 / 13.0, -3.0 / 13.0, -3.0 / 13.0, 23.0 / 39.0;
  ASSERT_MATRIX_NEAR(filter.covariance(0), p2, 1e-14);
  EXPECT_NEAR(filter.last_innovation(1), -1.2, 1e-14);
  EXPECT_NEAR(filter.last_innovation_variance(1), 7.4, 1e-14);
  ASSERT_MATRIX_NEAR(filter.estimate(1), Eigen::Vector2d(9.0 / 37.0, -12.0 / 37.0), 1e-14);
  Eigen::Matrix2d p3;
  p3 << 33.0 / 74.0, -22.0 / 37.0, -22.0 / 37.0, 54.0 / 37.0;
  ASSERT_MATRIX_NEAR(filter.covariance(1), p3, 1e-14);

  double est[4], sd[4];
  filter.estimates(est);
  filter.std_devs(sd);
  EXPECT_NEAR(est[1], 4.0 / 3.0, 1e-14);
  EXPECT_NEAR(est[2], 9.0 / 37.0, 1e-14);
  EXPECT_NEAR(sd[0], std::sqrt(17.0 / 13.0), 1e-14);
  EXPECT_NEAR(sd[3], std::sqrt(54.0 / 37.0), 1e-14);
  EXPECT_EQ(filter.counters().updated, 2u);
  EXPECT_EQ(filter.counters().warm_up, 1u);
}

// The split filter must equal the dense stacked 24-state filter (block-diagonal H[n], dense P), including
// warm-up, discontinuities and rejected samples, with different noise per outcome.
TEST(SvarKalmanFilter, SplitEqualsDenseStackedFilter) {
  estimation::SvarLayout layout(spec_g(4, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.02, 1.0}, {1e-3, 0.05, 0.5}, {1e-5, 0.01, 2.0}, {0.0, 0.1, 1.0}};
  test::Simulation sim = test::simulate_svar(layout, noise, 400, 11);
  sim.y(100, 2) = kNaN;
  sim.y(250, 0) = std::numeric_limits<double>::infinity();
  std::vector<bool> disc(400, false);
  disc[180] = true;
  disc[181] = true;  // consecutive flags: each restarts
  const test::DenseReference ref(layout, noise, sim.y, disc);

  estimation::SvarKalmanFilter filter(layout, noise);
  for (int n = 0; n < 400; ++n) {
    const Eigen::RowVectorXd row = sim.y.row(n);
    const estimation::SampleStatus st = filter.step(row.data(), disc[n]);
    ASSERT_EQ(st == estimation::SampleStatus::Updated, ref.updated[n]) << "n = " << n;
    Eigen::VectorXd x(24);
    filter.estimates(x.data());
    ASSERT_MATRIX_NEAR(x, ref.x_filt[n], 1e-10);
    for (int k = 0; k < 4; ++k) {
      ASSERT_MATRIX_NEAR(filter.covariance(k), ref.p_filt[n].block(6 * k, 6 * k, 6, 6), 1e-10);
      if (ref.updated[n]) {
        ASSERT_NEAR(filter.last_innovation(k), ref.innovations[n][k], 1e-10);
      }
    }
    // Off-diagonal blocks of the dense P stay exactly zero: the split is exact, not an approximation.
    ASSERT_EQ(ref.p_filt[n].block(0, 6, 6, 18).cwiseAbs().maxCoeff(), 0.0);
  }
  EXPECT_EQ(filter.counters().rejected_non_finite, 2u);
  EXPECT_EQ(filter.counters().warm_up, 1u + 1u + 1u + 1u + 1u);  // start, 2 flags, after NaN, after inf
  EXPECT_EQ(filter.counters().updated, 400u - 2u - 5u);
}

// After a discontinuity (M = 1) the flagged sample only fills the history; the next update regresses on the
// flagged sample, never on the one before the gap.
TEST(SvarKalmanFilter, DiscontinuityRestartsLagHistory) {
  estimation::SvarLayout layout(spec_g(3, 1));
  estimation::SvarKalmanFilter filter(layout, {estimation::NoiseParams{1e-3, 0.1, 1.0}});
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd y(60, 3);
  for (int i = 0; i < y.size(); ++i) y.data()[i] = normal(rng);
  y.row(29) *= 1000.0;  // sample before the gap: would dominate any regressor spanning the gap
  for (int n = 0; n < 30; ++n) {
    const Eigen::RowVectorXd row = y.row(n);
    filter.step(row.data());
  }
  const Eigen::VectorXd before = filter.estimate(0);
  Eigen::RowVectorXd row = y.row(30);
  EXPECT_EQ(filter.step(row.data(), true), estimation::SampleStatus::WarmUp);
  ASSERT_MATRIX_NEAR(filter.estimate(0), before, 0.0);  // no update
  const double innov_before = filter.last_innovation(0);
  row = y.row(31);
  EXPECT_EQ(filter.step(row.data()), estimation::SampleStatus::Updated);
  // outcome 1: h = (y2[31], y3[31], y2[30], y3[30])
  const Eigen::Vector4d h(y(31, 1), y(31, 2), y(30, 1), y(30, 2));
  const Eigen::Vector4d h_spanning(y(31, 1), y(31, 2), y(29, 1), y(29, 2));
  EXPECT_NEAR(filter.last_innovation(0), y(31, 0) - h.dot(before), 1e-12);
  EXPECT_GT(std::abs(filter.last_innovation(0) - (y(31, 0) - h_spanning.dot(before))), 1e-3);
  EXPECT_NE(filter.last_innovation(0), innov_before);

  // M = 3: the flagged sample and the next two are warm-up.
  estimation::ModelSpec s3 = spec_g(3, 3);
  estimation::SvarKalmanFilter f3(estimation::SvarLayout(s3), {estimation::NoiseParams{}});
  std::vector<estimation::SampleStatus> got;
  for (int n = 0; n < 12; ++n) {
    row = y.row(n);
    got.push_back(f3.step(row.data(), n == 6));
  }
  const std::vector<estimation::SampleStatus> expected = {
      estimation::SampleStatus::WarmUp,  estimation::SampleStatus::WarmUp,  estimation::SampleStatus::WarmUp,  estimation::SampleStatus::Updated,
      estimation::SampleStatus::Updated, estimation::SampleStatus::Updated, estimation::SampleStatus::WarmUp,  estimation::SampleStatus::WarmUp,
      estimation::SampleStatus::WarmUp,  estimation::SampleStatus::Updated, estimation::SampleStatus::Updated, estimation::SampleStatus::Updated};
  EXPECT_EQ(got, expected);
}

// Non-finite samples: rejected and counted; time still passes (P += q I); the next M samples re-fill history.
TEST(SvarKalmanFilter, NonFiniteSamplesAreRejectedAndCounted) {
  estimation::SvarLayout layout(spec_g(3, 2));
  const double q = 1e-3;
  estimation::SvarKalmanFilter filter(layout, {estimation::NoiseParams{q, 0.1, 1.0}});
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  double y[3];
  for (int n = 0; n < 20; ++n) {
    for (double& v : y) v = normal(rng);
    filter.step(y);
  }
  const Eigen::MatrixXd p_before = filter.covariance(1);
  const Eigen::VectorXd x_before = filter.estimate(1);
  y[1] = kNaN;
  EXPECT_EQ(filter.step(y), estimation::SampleStatus::RejectedNonFinite);
  const Eigen::MatrixXd expected_p =
      p_before + q * Eigen::MatrixXd::Identity(p_before.rows(), p_before.cols());
  ASSERT_MATRIX_NEAR(filter.covariance(1), expected_p, 1e-15);
  ASSERT_MATRIX_NEAR(filter.estimate(1), x_before, 0.0);
  y[1] = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(filter.step(y), estimation::SampleStatus::RejectedNonFinite);
  for (double& v : y) v = normal(rng);
  EXPECT_EQ(filter.step(y), estimation::SampleStatus::WarmUp);
  EXPECT_EQ(filter.step(y), estimation::SampleStatus::WarmUp);
  EXPECT_EQ(filter.step(y), estimation::SampleStatus::Updated);
  EXPECT_EQ(filter.counters().rejected_non_finite, 2u);
  EXPECT_EQ(filter.counters().warm_up, 2u + 2u);
  EXPECT_EQ(filter.counters().updated, 18u + 1u);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(filter.last_innovation(k)));
}

// 200 000 steps with tight measurement noise, tiny q, nearly collinear channels: every P_k stays symmetric
// positive definite.
TEST(SvarKalmanFilter, CovarianceStaysSymmetricPositiveDefiniteOverLongRuns) {
  estimation::SvarLayout layout(spec_g(4, 1));
  estimation::SvarKalmanFilter filter(layout, {estimation::NoiseParams{1e-10, 1e-8, 1.0}});
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  double y[4];
  for (int n = 0; n < 200000; ++n) {
    const double common = normal(rng);
    y[0] = common + 1e-6 * normal(rng);
    y[1] = common + 1e-6 * normal(rng);  // y1 ~ y2: near-collinear regressors for outcomes 3, 4
    y[2] = 0.5 * y[0] + 1e-4 * normal(rng);
    y[3] = normal(rng);
    filter.step(y);
    if (n % 50000 == 49999) {
      for (int k = 0; k < 4; ++k) {
        const Eigen::MatrixXd p = filter.covariance(k);
        EXPECT_SPD(p, 0.0) << "n = " << n << ", k = " << k;
        EXPECT_EQ((p - p.transpose()).cwiseAbs().maxCoeff(), 0.0);  // exactly symmetric after symmetrising
      }
    }
  }
  EXPECT_EQ(filter.counters().updated, 199999u);
}

// Masks give outcomes of different dimensions (separate SIMD lane groups) and one outcome without factors
// (its innovation is y itself): still identical to the dense stacked filter.
TEST(SvarKalmanFilter, MixedDimensionsAndEmptyOutcomeMatchDense) {
  estimation::ModelSpec spec = spec_g(5, 2);
  spec.allowed.assign(5, std::vector<bool>(5, true));
  spec.allowed[0] = {true, false, false, false, false};  // outcome 1: no parents at all -> no factors
  spec.instantaneous_allowed = {{false, false, false, false, false},
                                {true, false, false, false, false},
                                {true, true, false, false, false},
                                {true, true, true, false, false},
                                {true, true, true, true, false}};
  spec.include_self_lags = true;
  estimation::SvarLayout layout(spec);
  ASSERT_EQ(layout.factor_count(0), 2);  // only the self lags survive
  spec.include_self_lags = false;
  estimation::SvarLayout no_self(spec);
  ASSERT_EQ(no_self.factor_count(0), 0);
  for (const estimation::SvarLayout* l : {&layout, &no_self}) {
    const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.02, 1.0}, {1e-3, 0.05, 0.5}, {1e-5, 0.01, 2.0},
                                            {0.0, 0.1, 1.0}, {2e-4, 0.03, 1.5}};
    test::Simulation sim = test::simulate_svar(*l, noise, 250, 17, 0.1);
    sim.y(90, 4) = kNaN;
    std::vector<bool> disc(250, false);
    disc[150] = true;
    const test::DenseReference ref(*l, noise, sim.y, disc);
    estimation::SvarKalmanFilter filter(*l, noise);
    Eigen::VectorXd x(l->total_factors());
    for (int n = 0; n < 250; ++n) {
      const Eigen::RowVectorXd row = sim.y.row(n);
      filter.step(row.data(), disc[n]);
      filter.estimates(x.data());
      ASSERT_MATRIX_NEAR(x, ref.x_filt[n], 1e-10) << "n = " << n;
      if (ref.updated[n]) {
        for (int k = 0; k < 5; ++k) ASSERT_NEAR(filter.last_innovation(k), ref.innovations[n][k], 1e-10);
      }
    }
    for (int k = 0; k < 5; ++k) {
      const int d = l->factor_count(k), o = l->offset(k);
      ASSERT_MATRIX_NEAR(filter.covariance(k), ref.p_filt[249].block(o, o, d, d), 1e-10);
    }
    if (l->factor_count(0) == 0) {
      EXPECT_EQ(filter.last_innovation_variance(0), 0.02);  // no factors: S = r, e = y
    }
  }
}

TEST(SvarKalmanFilter, GenericDimensionPathMatchesDenseReference) {
  // G = 6, M = 2: 15 factors per outcome, beyond the fixed-size kernels (<= 14).
  estimation::SvarLayout layout(spec_g(6, 2));
  ASSERT_GT(layout.factor_count(0), 14);
  const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.05, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 120, 21, 0.05);
  const test::DenseReference ref(layout, noise, sim.y);
  ASSERT_NO_FATAL_FAILURE(expect_filter_matches_dense(layout, noise, sim, ref, 5, 15));
}

// d = 13 (G = 7, M = 1, self lags) and d = 14 (G = 8, M = 1: the eight-channel model) have fixed-size kernels
// of their own (kernels.hpp); filter and RTS smoother against the dense stacked reference.
TEST(SvarKalmanFilter, FixedKernelsOfDimension13And14MatchDenseReference) {
  for (const auto& [g, self_lags, d] : {std::tuple{7, true, 13}, std::tuple{8, false, 14}}) {
    SCOPED_TRACE("d = " + std::to_string(d));
    estimation::ModelSpec spec = spec_g(g, 1);
    spec.include_self_lags = self_lags;
    estimation::SvarLayout layout(spec);
    ASSERT_EQ(layout.factor_count(0), d);
    const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.05, 1.0}};
    const test::Simulation sim = test::simulate_svar(layout, noise, 150, 23, 0.05);
    const test::DenseReference ref(layout, noise, sim.y);
    ASSERT_NO_FATAL_FAILURE(expect_filter_matches_dense(layout, noise, sim, ref, g - 1, d));
    const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, sim.y);
    for (int n = 0; n < 150; n += 7) ASSERT_MATRIX_NEAR(rts.estimates.row(n).transpose(), ref.x_smooth[n], 1e-9);
  }
}

TEST(SvarKalmanFilter, ResetRestoresPriorAndSetNoiseApplies) {
  estimation::SvarLayout layout(spec_g(2, 1));
  estimation::SvarKalmanFilter filter(layout, {estimation::NoiseParams{0.5, 1.0, 2.0}});
  const double y[] = {1.0, 2.0};
  filter.step(y);
  filter.step(y);
  filter.reset();
  EXPECT_EQ(filter.counters().updated, 0u);
  EXPECT_EQ(filter.samples_seen(), 0u);
  ASSERT_MATRIX_NEAR(filter.covariance(0), 2.0 * Eigen::Matrix2d::Identity(), 0.0);
  EXPECT_TRUE(std::isnan(filter.last_innovation(0)));
  filter.set_noise(1, estimation::NoiseParams{0.25, 1.0, 3.0});
  filter.step(y);
  filter.step(y);  // predict adds the new q = 0.25 for outcome 2 before the update
  // outcome 2: P = 2.25 I, h = (1, 1): S = 4.5 + 1
  EXPECT_NEAR(filter.last_innovation_variance(1), 5.5, 1e-15);
  EXPECT_NEAR(filter.last_innovation_variance(0), 2.5 * 8 + 1.0, 1e-15);  // h = (2, 2), P = 2.5 I
}

TEST(SvarKalmanFilter, InvalidNoiseThrows) {
  estimation::SvarLayout layout(spec_g(3, 1));
  EXPECT_THROW(estimation::SvarKalmanFilter(layout, {}), std::invalid_argument);
  EXPECT_THROW(estimation::SvarKalmanFilter(layout, {estimation::NoiseParams{}, estimation::NoiseParams{}}), std::invalid_argument);
  EXPECT_THROW(estimation::SvarKalmanFilter(layout, {estimation::NoiseParams{-1.0, 1.0, 1.0}}), std::invalid_argument);
  EXPECT_THROW(estimation::SvarKalmanFilter(layout, {estimation::NoiseParams{0.0, 0.0, 1.0}}), std::invalid_argument);
  EXPECT_THROW(estimation::SvarKalmanFilter(layout, {estimation::NoiseParams{0.0, 1.0, kNaN}}), std::invalid_argument);
  try {
    estimation::SvarKalmanFilter f(layout, {estimation::NoiseParams{}, estimation::NoiseParams{}, estimation::NoiseParams{1e-6, -2.0, 1.0}});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("noise[2].r = -2"), std::string::npos) << e.what();
  }
}

// Checkpoint: a filter restored into a fresh object (built with other noise: q, r, p0 come from the
// checkpoint) continues bit for bit like the uninterrupted one, for every cut of a run with a discontinuity,
// a rejected sample, lag order 2 and outcomes of different dimension (lane padding). Another model throws.
TEST(SvarKalmanFilterCheckpoint, RestoredFilterContinuesBitForBit) {
  estimation::ModelSpec spec = spec_g(5, 2);
  spec.instantaneous_allowed.assign(5, std::vector<bool>(5, true));
  spec.instantaneous_allowed[0][3] = false;  // outcomes 0 and 2 lose a factor: two lane groups
  spec.instantaneous_allowed[2][1] = false;
  const estimation::SvarLayout layout(spec);
  std::vector<estimation::NoiseParams> noise;
  for (int k = 0; k < 5; ++k) noise.push_back(estimation::NoiseParams{1e-5 * (k + 1), 0.05 + 0.01 * k, 0.7});
  const auto sim = test::simulate_svar(layout, noise, 120, 8);
  Eigen::MatrixXd y = sim.y;
  y(40, 2) = kNaN;
  auto disc = [](int n) { return n == 0 || n == 70; };
  auto bits = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
  };
  for (int cut : {0, 1, 2, 39, 40, 41, 70, 71, 119}) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    estimation::SvarKalmanFilter whole(layout, noise), first(layout, noise);
    for (int n = 0; n < cut; ++n) {
      const Eigen::RowVectorXd row = y.row(n);
      whole.step(row.data(), disc(n));
      first.step(row.data(), disc(n));
    }
    estimation::StateWriter w;
    first.save(w);
    estimation::SvarKalmanFilter restored(layout, {estimation::NoiseParams{1.0, 1.0, 1.0}});
    estimation::StateReader r(w.bytes());
    restored.restore(r);
    EXPECT_TRUE(r.at_end());
    for (int n = cut; n < 120; ++n) {
      const Eigen::RowVectorXd row = y.row(n);
      ASSERT_EQ(restored.step(row.data(), disc(n)), whole.step(row.data(), disc(n))) << "sample " << n;
      for (int k = 0; k < 5; ++k) {
        ASSERT_TRUE(bits(restored.estimate(k), whole.estimate(k))) << "sample " << n << " outcome " << k;
        ASSERT_TRUE(bits(restored.covariance(k), whole.covariance(k))) << "sample " << n << " outcome " << k;
        const double e1 = restored.last_innovation(k), e2 = whole.last_innovation(k);
        ASSERT_EQ(std::memcmp(&e1, &e2, sizeof e1), 0) << "sample " << n;
      }
    }
    EXPECT_EQ(restored.samples_seen(), whole.samples_seen());
    EXPECT_EQ(restored.counters().updated, whole.counters().updated);
    EXPECT_EQ(restored.counters().warm_up, whole.counters().warm_up);
    EXPECT_EQ(restored.counters().rejected_non_finite, whole.counters().rejected_non_finite);
    EXPECT_EQ(restored.noise(3).q, noise[3].q);
  }
}

TEST(SvarKalmanFilterCheckpoint, AnotherModelOrADamagedCheckpointThrows) {
  estimation::SvarKalmanFilter filter(estimation::SvarLayout(spec_g(4, 1)), {estimation::NoiseParams{}});
  estimation::StateWriter w;
  filter.save(w);
  auto message = [&](const estimation::ModelSpec& spec) -> std::string {
    estimation::SvarKalmanFilter other(estimation::SvarLayout(spec), {estimation::NoiseParams{}});
    estimation::StateReader r(w.bytes());
    try {
      other.restore(r);
    } catch (const estimation::StateError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(spec_g(8, 1)), "checkpoint has 4 channels, this filter has 8");
  EXPECT_EQ(message(spec_g(4, 2)), "checkpoint has lag order 1, this filter has 2");
  for (std::size_t n = 0; n < w.bytes().size(); n += 7) {
    estimation::SvarKalmanFilter other(estimation::SvarLayout(spec_g(4, 1)), {estimation::NoiseParams{}});
    estimation::StateReader r(w.bytes().substr(0, n));
    EXPECT_THROW(other.restore(r), estimation::StateError) << "truncated to " << n;
  }
}

}  // namespace
}  // namespace causal
