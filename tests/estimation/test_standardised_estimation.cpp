// estimate_standardised / robust_channel_scales: scales against hand-computed values; scale invariance
// against the unscaled run through the exact unit relation x_kj = z-factor * s_k / s_j; refusals of dead and
// constant channels; a non-finite estimate comes back as a status naming factor, channel and row.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "causal/estimation/standardised_estimation.hpp"
#include "svar_test_support.hpp"

namespace causal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(RobustChannelScales, MatchHandComputedValues) {
  Eigen::MatrixXd w(5, 6);
  // col 0: |y| = 1..5, median 3;  col 1: mostly zeros -> root mean square sqrt(8/4)... over finite values
  // col 2: constant 5;  col 3: all zeros;  col 4: no finite value;  col 5: 5 + rounding-level wiggle
  w << 1, 0, 5, 0, kNaN, 5,
      -2, 0, 5, 0, kNaN, 5 + 1e-15,
      3, 0, 5, 0, kNaN, 5,
      -4, 2, 5, 0, kNaN, 5 - 1e-15,
      5, kNaN, 5, 0, kNaN, 5;
  const estimation::ChannelScales s = estimation::robust_channel_scales(w);
  ASSERT_EQ(s.status.size(), 6u);
  EXPECT_EQ(s.status[0], estimation::ScaleStatus::Ok);
  EXPECT_DOUBLE_EQ(s.scale[0], 3.0 / 0.6744897501960817);
  EXPECT_EQ(s.status[1], estimation::ScaleStatus::Ok);           // values 0,0,0,2: median |y| = 0 -> rms = sqrt(4/4)
  EXPECT_DOUBLE_EQ(s.scale[1], 1.0);
  EXPECT_EQ(s.status[2], estimation::ScaleStatus::ConstantChannel);
  EXPECT_EQ(s.status[3], estimation::ScaleStatus::ConstantChannel);
  EXPECT_EQ(s.status[4], estimation::ScaleStatus::NoFiniteValues);
  EXPECT_EQ(s.status[5], estimation::ScaleStatus::ConstantChannel);  // spread 6e-16 of its level: rounding, not signal
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.first_refused(), 2);
}

TEST(RobustChannelScales, ScaleIsEquivariantUpToTheTopOfTheDoubleRange) {
  Eigen::MatrixXd w(7, 1);
  w << 0.3, -1.2, 2.5, -0.7, 0.1, 4.0, -3.3;
  const double base = estimation::robust_channel_scales(w).scale[0];
  for (double f : {1e-200, 1e-9, 1e6, 1e160, 1e250}) {
    const estimation::ChannelScales s = estimation::robust_channel_scales(w * f);
    ASSERT_TRUE(s.ok()) << f;
    EXPECT_NEAR(s.scale[0] / (base * f), 1.0, 1e-15) << f;
  }
  EXPECT_EQ(estimation::robust_channel_scales(w * 1e-300).status[0], estimation::ScaleStatus::OutOfRange);
}

struct Data {
  estimation::SvarLayout layout;
  Eigen::MatrixXd y;
};

Data simulated(int n = 800) {
  estimation::ModelSpec spec;
  spec.channels = 4;
  estimation::SvarLayout layout(spec);
  const test::Simulation sim = test::simulate_svar(layout, {estimation::NoiseParams{1e-6, 0.05, 1.0}}, n, 11);
  return {layout, sim.y};
}

// Factor column c of `scaled` converted back to the units of the unscaled data: channel ch was multiplied by f.
double unit_factor(const estimation::SvarLayout& layout, Eigen::Index c, int ch, double f) {
  int k = 0;
  while (k + 1 < layout.channels() && layout.offset(k + 1) <= c) ++k;
  const int j = layout.regressors(k)[c - layout.offset(k)].channel;
  double u = 1.0;
  if (k == ch) u /= f;  // x_kj scales by s_k / s_j
  if (j == ch) u *= f;
  return u;
}

TEST(StandardisedEstimation, OneChannelInOtherUnitsGivesTheSameFactorsUpToTheExactScale) {
  const Data d = simulated();
  for (bool auto_noise : {false, true}) {
    for (estimation::EstimatorKind kind : {estimation::EstimatorKind::Filter, estimation::EstimatorKind::FixedLag, estimation::EstimatorKind::Rts}) {
      estimation::StandardisedOptions opt;
      opt.estimator = kind;
      opt.lag = 20;
      opt.auto_noise = auto_noise;
      opt.calibration_samples = 400;
      const estimation::StandardisedRun base = estimation::estimate_standardised(d.layout, d.y, {}, opt);
      ASSERT_EQ(base.status, estimation::EstimationStatus::Ok) << base.message;
      for (double f : {1e6, 1e-9}) {
        SCOPED_TRACE(testing::Message() << "auto_noise " << auto_noise << " estimator " << static_cast<int>(kind)
                                        << " factor " << f);
        Eigen::MatrixXd y = d.y;
        y.col(1) *= f;
        const estimation::StandardisedRun run = estimation::estimate_standardised(d.layout, y, {}, opt);
        ASSERT_EQ(run.status, estimation::EstimationStatus::Ok) << run.message;
        EXPECT_NEAR(run.scales.scale[1] / (base.scales.scale[1] * f), 1.0, 1e-14);
        double worst = 0.0;
        for (Eigen::Index c = 0; c < base.run.estimates.cols(); ++c) {
          const double u = unit_factor(d.layout, c, 1, f);
          for (Eigen::Index i = 0; i < y.rows(); ++i) {
            ASSERT_TRUE(std::isfinite(run.run.estimates(i, c)) && std::isfinite(run.run.std_devs(i, c)));
            worst = std::max(worst, std::abs(run.run.estimates(i, c) * u - base.run.estimates(i, c)));
            worst = std::max(worst, std::abs(run.run.std_devs(i, c) * u - base.run.std_devs(i, c)));
          }
        }
        EXPECT_LT(worst, 1e-9);
        for (int k = 0; k < 4; ++k) {  // innovations in the user's units
          const double u = k == 1 ? f : 1.0;
          EXPECT_NEAR(run.run.innovations(500, k), base.run.innovations(500, k) * u,
                      1e-9 * std::abs(base.run.innovations(500, k) * u));
        }
      }
    }
  }
}

// The raw (unstandardised) estimate is NOT invariant: this is the failure the standardisation removes.
TEST(StandardisedEstimation, RawUnitsDependOnTheUnitsAndStandardisedRecoversTheRawAccuracy) {
  estimation::ModelSpec spec;
  spec.channels = 4;
  estimation::SvarLayout layout(spec);
  const test::Simulation sim = test::simulate_svar(layout, {estimation::NoiseParams{1e-6, 0.05, 1.0}}, 2000, 5);
  Eigen::MatrixXd y = sim.y;
  y.col(1) *= 1e6;
  auto rmse = [&](const estimation::StandardisedRun& r, double f) {
    double ss = 0.0;
    long cnt = 0;
    for (Eigen::Index c = 0; c < sim.x.cols(); ++c) {
      const double u = unit_factor(layout, c, 1, f);
      for (Eigen::Index i = 500; i < y.rows(); ++i, ++cnt) ss += std::pow(r.run.estimates(i, c) * u - sim.x(i, c), 2);
    }
    return std::sqrt(ss / static_cast<double>(cnt));
  };
  estimation::StandardisedOptions opt;
  opt.auto_noise = true;
  opt.calibration_samples = 1000;
  opt.standardise = false;
  const double raw_unit = rmse(estimation::estimate_standardised(layout, sim.y, {}, opt), 1.0);
  const double raw_scaled = rmse(estimation::estimate_standardised(layout, y, {}, opt), 1e6);
  opt.standardise = true;
  const double std_scaled = rmse(estimation::estimate_standardised(layout, y, {}, opt), 1e6);
  std::cout << "factor RMSE: raw units " << raw_unit << ", raw with channel 2 x1e6 " << raw_scaled
            << ", standardised with channel 2 x1e6 " << std_scaled << "\n";
  EXPECT_GT(raw_scaled, 1.3 * raw_unit);
  EXPECT_LT(std_scaled, 1.1 * raw_unit);
}

TEST(StandardisedEstimation, DeadAndStuckChannelsAreRefusedByName) {
  const Data d = simulated(300);
  for (double level : {0.0, 3.7}) {
    Eigen::MatrixXd y = d.y;
    y.col(2).setConstant(level);
    for (bool auto_noise : {false, true}) {
      estimation::StandardisedOptions opt;
      opt.auto_noise = auto_noise;
      const estimation::StandardisedRun run = estimation::estimate_standardised(d.layout, y, {}, opt, {"a", "b", "c", "d"});
      EXPECT_EQ(run.status, estimation::EstimationStatus::ConstantChannel);
      EXPECT_EQ(run.channel, 2);
      EXPECT_NE(run.message.find("channel 3 'c' is constant"), std::string::npos) << run.message;
      EXPECT_EQ(run.run.estimates.size(), 0);
    }
  }
  // Dead only in the calibration window: refused too (its factors would be learned from nothing).
  Eigen::MatrixXd y = d.y;
  y.block(0, 0, 100, 1).setZero();
  estimation::StandardisedOptions opt;
  opt.calibration_samples = 100;
  EXPECT_EQ(estimation::estimate_standardised(d.layout, y, {}, opt).status, estimation::EstimationStatus::ConstantChannel);
}

TEST(StandardisedEstimation, NonFiniteEstimateIsAStatusNamingFactorChannelAndRow) {
  Data d = simulated(200);
  d.y *= 1e160;  // raw units: h^T P h overflows at the first update
  estimation::StandardisedOptions opt;
  opt.standardise = false;
  opt.estimator = estimation::EstimatorKind::Filter;
  const estimation::StandardisedRun raw = estimation::estimate_standardised(d.layout, d.y, {}, opt, {"a", "b", "c", "d"});
  ASSERT_EQ(raw.status, estimation::EstimationStatus::NonFiniteOutput);
  EXPECT_EQ(raw.row, 1);  // row 0 is warm-up (M = 1): the prediction, still finite
  EXPECT_EQ(raw.channel, 0);
  EXPECT_EQ(raw.factor, "x12");
  EXPECT_NE(raw.message.find("factor x12 (outcome channel 1 'a', regressor channel 2 'b') is not finite at row 1"),
            std::string::npos)
      << raw.message;
  // Standardised, the same data is an ordinary estimate.
  opt.standardise = true;
  const estimation::StandardisedRun fine = estimation::estimate_standardised(d.layout, d.y, {}, opt);
  EXPECT_EQ(fine.status, estimation::EstimationStatus::Ok) << fine.message;
  EXPECT_TRUE(fine.run.estimates.allFinite());
}

}  // namespace
}  // namespace causal
