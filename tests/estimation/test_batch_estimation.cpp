// run_filter / run_rts_smoother / run_fixed_lag_smoother: agreement with the streaming filter and with the
// dense reference, and accuracy ordering on data simulated with known time-varying factors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "causal/estimation/batch_estimation.hpp"
#include "matrix_asserts.hpp"
#include "svar_test_support.hpp"

namespace causal {
namespace {

using test::kNaN;
using test::spec_g;

struct GappyData {
  test::Simulation sim;
  std::vector<bool> disc;
};

GappyData gappy(const estimation::SvarLayout& layout, const std::vector<estimation::NoiseParams>& noise, int n, std::uint64_t seed) {
  GappyData d{test::simulate_svar(layout, noise, n, seed), std::vector<bool>(n, false)};
  d.sim.y(n / 3, 1) = kNaN;
  d.disc[n / 2] = true;
  return d;
}

TEST(BatchEstimation, RunFilterEqualsStreamingFilter) {
  estimation::SvarLayout layout(spec_g(4, 2));
  const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.02, 1.0}, {1e-3, 0.05, 0.5}, {1e-5, 0.01, 2.0}, {0.0, 0.1, 1.0}};
  const GappyData data = gappy(layout, noise, 300, 1);
  const estimation::EstimationRun run = estimation::run_filter(layout, noise, data.sim.y, data.disc);
  estimation::SvarKalmanFilter filter(layout, noise);
  const int f = layout.total_factors();
  Eigen::VectorXd x(f), sd(f);
  for (int n = 0; n < 300; ++n) {
    const Eigen::RowVectorXd row = data.sim.y.row(n);
    const estimation::SampleStatus st = filter.step(row.data(), data.disc[n]);
    ASSERT_EQ(run.status[n], st);
    filter.estimates(x.data());
    filter.std_devs(sd.data());
    ASSERT_MATRIX_NEAR(run.estimates.row(n).transpose(), x, 1e-13);
    ASSERT_MATRIX_NEAR(run.std_devs.row(n).transpose(), sd, 1e-13);
    for (int k = 0; k < 4; ++k) {
      if (st == estimation::SampleStatus::Updated) {
        ASSERT_NEAR(run.innovations(n, k), filter.last_innovation(k), 1e-13);
        ASSERT_NEAR(run.innovation_variances(n, k), filter.last_innovation_variance(k), 1e-13);
      } else {
        ASSERT_TRUE(std::isnan(run.innovations(n, k)));
        ASSERT_TRUE(std::isnan(run.innovation_variances(n, k)));
      }
    }
  }
  EXPECT_EQ(run.counters.updated, filter.counters().updated);
  EXPECT_EQ(run.counters.warm_up, filter.counters().warm_up);
  EXPECT_EQ(run.counters.rejected_non_finite, 1u);
}

// Filter and RTS against the dense stacked reference (independent textbook implementation in the test).
TEST(BatchEstimation, FilterAndRtsEqualDenseReference) {
  estimation::SvarLayout layout(spec_g(4, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.02, 1.0}, {1e-3, 0.05, 0.5}, {1e-5, 0.01, 2.0}, {0.0, 0.1, 1.0}};
  const GappyData data = gappy(layout, noise, 500, 2);
  const test::DenseReference ref(layout, noise, data.sim.y, data.disc);
  const estimation::EstimationRun filt = estimation::run_filter(layout, noise, data.sim.y, data.disc);
  const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, data.sim.y, data.disc);
  for (int n = 0; n < 500; ++n) {
    ASSERT_MATRIX_NEAR(filt.estimates.row(n).transpose(), ref.x_filt[n], 1e-9);
    ASSERT_MATRIX_NEAR(filt.std_devs.row(n).transpose(), ref.p_filt[n].diagonal().cwiseSqrt(), 1e-9);
    ASSERT_MATRIX_NEAR(rts.estimates.row(n).transpose(), ref.x_smooth[n], 1e-9) << "n = " << n;
    ASSERT_MATRIX_NEAR(rts.std_devs.row(n).transpose(), ref.p_smooth[n].diagonal().cwiseSqrt(), 1e-9);
  }
  // Smoothing only adds information: smoothed variances never exceed filtered ones.
  EXPECT_LE((rts.std_devs - filt.std_devs).maxCoeff(), 1e-12);
  // The innovations of the RTS run are the filter's.
  ASSERT_TRUE(rts.innovations.bottomRows(10).isApprox(filt.innovations.bottomRows(10)));
}

// RTS smooths block by block (kRtsBlock samples, recomputed from filter checkpoints): across block boundaries,
// a gap and a rejected sample it must still equal the dense textbook smoother over the whole record.
TEST(BatchEstimation, BlockwiseRtsEqualsDenseReferenceAcrossBlocks) {
  estimation::SvarLayout layout(spec_g(3, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-6, 0.02, 1.0}, {1e-5, 0.05, 0.5}, {1e-6, 0.01, 2.0}};
  const int n = static_cast<int>(2 * estimation::kRtsBlock + 37);
  GappyData data = gappy(layout, noise, n, 12);
  data.disc[estimation::kRtsBlock] = true;           // a segment starts exactly at a block boundary
  data.sim.y(estimation::kRtsBlock - 1, 0) = kNaN;   // and the sample before it is rejected
  ASSERT_LT(data.sim.y.cwiseAbs().maxCoeff(), 1e3);  // NaN-aware: the simulated system stayed stable
  const test::DenseReference ref(layout, noise, data.sim.y, data.disc);
  const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, data.sim.y, data.disc);
  ASSERT_EQ(rts.estimates.rows(), n);
  for (int i = 0; i < n; ++i) {
    ASSERT_MATRIX_NEAR(rts.estimates.row(i).transpose(), ref.x_smooth[i], 1e-9) << "n = " << i;
    ASSERT_MATRIX_NEAR(rts.std_devs.row(i).transpose(), ref.p_smooth[i].diagonal().cwiseSqrt(), 1e-9);
  }
}

// Decimated output keeps exactly the rows of the full run (every = 7: row i is sample 7 i).
TEST(BatchEstimation, DecimatedOutputKeepsExactlyTheFullRunsRows) {
  estimation::SvarLayout layout(spec_g(4, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-6, 0.02, 1.0}};
  const int n = static_cast<int>(estimation::kRtsBlock + 500);
  const GappyData data = gappy(layout, noise, n, 21);
  const estimation::BatchOutput every7{7};
  const estimation::EstimationRun full[] = {estimation::run_filter(layout, noise, data.sim.y, data.disc),
                                estimation::run_rts_smoother(layout, noise, data.sim.y, data.disc),
                                estimation::run_fixed_lag_smoother(layout, noise, data.sim.y, data.disc, 9)};
  const estimation::EstimationRun dec[] = {estimation::run_filter(layout, noise, data.sim.y, data.disc, every7),
                               estimation::run_rts_smoother(layout, noise, data.sim.y, data.disc, every7),
                               estimation::run_fixed_lag_smoother(layout, noise, data.sim.y, data.disc, 9, every7)};
  for (int e = 0; e < 3; ++e) {
    ASSERT_EQ(dec[e].estimates.rows(), (n + 6) / 7);
    for (Eigen::Index i = 0; i < dec[e].estimates.rows(); ++i) {
      ASSERT_EQ(dec[e].estimates.row(i), full[e].estimates.row(7 * i)) << e << " " << i;
      ASSERT_EQ(dec[e].std_devs.row(i), full[e].std_devs.row(7 * i)) << e << " " << i;
    }
    ASSERT_EQ(dec[e].innovations.rows(), n);  // innovations stay per sample
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 4; ++k) {
        const double a = dec[e].innovations(i, k), b = full[e].innovations(i, k);
        ASSERT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << e << " " << i << " " << k;
      }
    }
  }
  // Without innovations: the same estimates, no per-sample innovation storage.
  const estimation::EstimationRun lean = estimation::run_rts_smoother(layout, noise, data.sim.y, data.disc, estimation::BatchOutput{7, false});
  EXPECT_EQ(lean.innovations.rows(), 0);
  EXPECT_EQ(lean.innovation_variances.rows(), 0);
  EXPECT_EQ(lean.estimates, dec[1].estimates);
  EXPECT_EQ(lean.std_devs, dec[1].std_devs);
  EXPECT_THROW(estimation::run_filter(layout, noise, data.sim.y, data.disc, estimation::BatchOutput{0}), std::invalid_argument);
}

TEST(BatchEstimation, RtsMatchesDenseReferenceOnGenericDimensionPath) {
  estimation::SvarLayout layout(spec_g(5, 3));  // 16 factors per outcome: dynamic-size kernels
  const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.05, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 150, 9, 0.04);
  const test::DenseReference ref(layout, noise, sim.y);
  const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, sim.y);
  for (int n = 0; n < 150; ++n) {
    ASSERT_MATRIX_NEAR(rts.estimates.row(n).transpose(), ref.x_smooth[n], 1e-9);
    ASSERT_MATRIX_NEAR(rts.std_devs.row(n).transpose(), ref.p_smooth[n].diagonal().cwiseSqrt(), 1e-9);
  }
}

TEST(BatchEstimation, MaskedModelRtsMatchesDenseReference) {
  estimation::ModelSpec spec = spec_g(4, 2);
  spec.allowed = {{true, false, false, false}, {true, true, true, true}, {true, true, true, false},
                  {true, false, true, true}};
  spec.include_self_lags = true;
  estimation::SvarLayout layout(spec);
  const std::vector<estimation::NoiseParams> noise = {{1e-4, 0.02, 1.0}, {1e-3, 0.05, 0.5}, {1e-5, 0.01, 2.0}, {0.0, 0.1, 1.0}};
  const GappyData data = gappy(layout, noise, 300, 4);
  const test::DenseReference ref(layout, noise, data.sim.y, data.disc);
  const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, data.sim.y, data.disc);
  for (int n = 0; n < 300; ++n) {
    ASSERT_MATRIX_NEAR(rts.estimates.row(n).transpose(), ref.x_smooth[n], 1e-9) << "n = " << n;
    ASSERT_MATRIX_NEAR(rts.std_devs.row(n).transpose(), ref.p_smooth[n].diagonal().cwiseSqrt(), 1e-9);
  }
}

double rmse(const Eigen::MatrixXd& est, const Eigen::MatrixXd& truth, int from) {
  const Eigen::MatrixXd d = est.bottomRows(est.rows() - from) - truth.bottomRows(truth.rows() - from);
  return std::sqrt(d.squaredNorm() / static_cast<double>(d.size()));
}

// G = 4, M = 1, 5000 samples, true factors random walks with the filter's q. Instantaneous links follow a
// causal order (lower triangular): with instantaneous cycles the contemporaneous regressors would be
// correlated with e_k (simultaneity) and the factors would not be what a per-outcome regression estimates.
TEST(BatchEstimation, SmootherBeatsFixedLagBeatsFilterOnSimulatedData) {
  estimation::ModelSpec spec = spec_g(4, 1);
  spec.instantaneous_allowed = {{false, false, false, false},
                                {true, false, false, false},
                                {true, true, false, false},
                                {true, true, true, false}};
  estimation::SvarLayout layout(spec);
  const std::vector<estimation::NoiseParams> noise = {{2e-5, 1e-2, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 5000, 42);
  ASSERT_LT(sim.y.cwiseAbs().maxCoeff(), 10.0) << "simulated system drifted unstable; pick another seed";
  const estimation::EstimationRun filt = estimation::run_filter(layout, noise, sim.y);
  const estimation::EstimationRun lag = estimation::run_fixed_lag_smoother(layout, noise, sim.y, {}, 50);
  const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, sim.y);
  const int burn_in = 200;  // the prior x = 0 dominates the first samples for every estimator
  const double e_filt = rmse(filt.estimates, sim.x, burn_in);
  const double e_lag = rmse(lag.estimates, sim.x, burn_in);
  const double e_rts = rmse(rts.estimates, sim.x, burn_in);
  RecordProperty("rmse_filter", std::to_string(e_filt));
  RecordProperty("rmse_fixed_lag_50", std::to_string(e_lag));
  RecordProperty("rmse_rts", std::to_string(e_rts));
  EXPECT_LT(e_rts, e_lag);
  EXPECT_LT(e_lag, e_filt);
  EXPECT_LT(e_rts, 0.8 * e_filt);  // a clear margin, not rounding noise
  // Coverage: about 95 % of true factors within 2 RTS standard deviations (model-consistent uncertainty).
  const Eigen::ArrayXXd z = ((rts.estimates - sim.x).array() / rts.std_devs.array()).bottomRows(5000 - burn_in);
  const double inside = (z.abs() < 2.0).cast<double>().mean();
  EXPECT_GT(inside, 0.90);
  EXPECT_LT(inside, 0.99);
}

TEST(BatchEstimation, BadShapesThrow) {
  estimation::SvarLayout layout(spec_g(3, 1));
  const Eigen::MatrixXd wrong_cols = Eigen::MatrixXd::Zero(10, 4);
  EXPECT_THROW(estimation::run_filter(layout, {estimation::NoiseParams{}}, wrong_cols), std::invalid_argument);
  const Eigen::MatrixXd ok = Eigen::MatrixXd::Ones(10, 3);
  EXPECT_THROW(estimation::run_rts_smoother(layout, {estimation::NoiseParams{}}, ok, std::vector<bool>(9, false)), std::invalid_argument);
  EXPECT_THROW(estimation::run_filter(layout, {estimation::NoiseParams{}, estimation::NoiseParams{}}, ok), std::invalid_argument);
  EXPECT_THROW(estimation::run_fixed_lag_smoother(layout, {estimation::NoiseParams{}}, ok, {}, -1), std::invalid_argument);
  const estimation::EstimationRun empty = estimation::run_rts_smoother(layout, {estimation::NoiseParams{}}, Eigen::MatrixXd(0, 3));
  EXPECT_EQ(empty.estimates.rows(), 0);
}

}  // namespace
}  // namespace causal
