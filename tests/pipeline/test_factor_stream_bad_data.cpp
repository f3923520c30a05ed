// causal::pipeline::FactorStream on bad data with automatic noise: nothing throws, nothing is NaN, and every
// fallback is said (warnings()). Split from test_factor_stream.cpp to keep files short.
#include "causal/pipeline/factor_stream.hpp"

#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace causal::pipeline {
namespace {

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000LL;
constexpr double kPeriod = 50'000.0;

estimation::ModelSpec spec(int g) {
  estimation::ModelSpec s;
  s.channels = g;
  s.lag_order = 1;
  return s;
}

// Configured values far from the data's, so a fallback is visible.
FactorStreamParams auto_params(const estimation::ModelSpec& s, std::size_t publish_every, std::size_t calibration) {
  FactorStreamParams p;
  p.model = s;
  p.noise.automatic = true;
  p.noise.fixed = estimation::NoiseParams{1e-3, 0.7, 0.5};
  p.noise.calibration_samples = calibration;
  p.publish_every = publish_every;
  return p;
}

std::vector<FactorReport> feed_all(FactorStream& stream, const RowMajorMatrix& y) {
  std::vector<FactorReport> out;
  Eigen::Index at = 0;
  for (Eigen::Index s : causal::test::irregular_blocks(y.rows())) {
    stream.feed(y.middleRows(at, s), static_cast<std::uint64_t>(at), at == 0, kT0 + static_cast<std::int64_t>(at) * 50'000, kPeriod, out);
    at += s;
  }
  stream.finish(out);
  return out;
}

// On main one value of 1e300 in the calibration window made tune_noise return q = inf and the stream threw
// (std::invalid_argument from the filter), ending the service for every asset group. Now the outcomes that
// cannot be tuned run the configured noise and warnings() says so, naming each one.
TEST(FactorStreamAutomatic, AbsurdValueInTheWindowFallsBackToTheConfiguredNoiseAndSaysSo) {
  const estimation::SvarLayout layout(spec(3));
  RowMajorMatrix y = causal::test::simulate_svar(layout, 1000, 61);
  y(100, 1) = 1e300;
  FactorStream stream(auto_params(layout.spec(), 64, 400));
  ASSERT_NO_THROW(feed_all(stream, y));
  ASSERT_TRUE(stream.calibrated());
  for (int k = 0; k < 3; ++k) {
    const auto& t = stream.tuning()[static_cast<std::size_t>(k)];
    const auto& n = stream.noise()[static_cast<std::size_t>(k)];
    if (t.usable) {
      EXPECT_DOUBLE_EQ(n.q, t.noise.q);
    } else {
      EXPECT_DOUBLE_EQ(n.q, 1e-3) << "outcome " << k;
      EXPECT_DOUBLE_EQ(n.r, 0.7) << "outcome " << k;
    }
  }
  // Every outcome regresses on channel 2 or is channel 2: none can be tuned, each one is named.
  ASSERT_EQ(stream.warnings().size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NE(stream.warnings()[static_cast<std::size_t>(k)].find("outcome " + std::to_string(k + 1)), std::string::npos);
  }
}

// Every report of a 3-channel run of 2000 samples at cadence 64 is there, finite, with no clamped standard deviation.
void expect_every_report_finite(const std::vector<FactorReport>& out) {
  ASSERT_EQ(out.size(), 3u * (2000 / 64));
  for (const auto& r : out) {
    EXPECT_TRUE(r.factors.allFinite() && r.std_devs.allFinite()) << r.outcome << " at " << r.sample_index;
    EXPECT_EQ(r.degenerate_std, 0u) << r.outcome << " at " << r.sample_index;
  }
}

// A dead channel with automatic noise gave NaN standard deviations on main (r tuned to ~1e-308). Its outcome
// now runs the configured noise; no report holds a NaN or a clamped (degenerate) standard deviation.
TEST(FactorStreamAutomatic, DeadChannelGivesNoNaN) {
  const estimation::SvarLayout layout(spec(3));
  RowMajorMatrix y = causal::test::simulate_svar(layout, 2000, 62);
  y.col(2).setZero();
  FactorStream stream(auto_params(layout.spec(), 64, 400));
  const auto out = feed_all(stream, y);
  ASSERT_NO_FATAL_FAILURE(expect_every_report_finite(out));
  EXPECT_FALSE(stream.tuning()[2].usable);
  ASSERT_EQ(stream.warnings().size(), 1u);
  EXPECT_NE(stream.warnings()[0].find("outcome 3"), std::string::npos) << stream.warnings()[0];
}

// A channel scaled by 1e-9 from the start: with the absolute p0 = 0.5 its outcome's prior is ~1e18 times its
// noise, every candidate's filter pass loses all precision (non-finite likelihood) and on main the first
// (failed) grid point was kept, giving NaN standard deviations. Now that outcome is a reported failure and
// runs the configured noise; nothing is NaN and no variance had to be clamped.
TEST(FactorStreamAutomatic, ChannelScaledBy1e9GivesNoNaN) {
  const estimation::SvarLayout layout(spec(3));
  RowMajorMatrix y = causal::test::simulate_svar(layout, 2000, 63);
  y.col(1) *= 1e-9;
  FactorStream stream(auto_params(layout.spec(), 64, 400));
  const auto out = feed_all(stream, y);
  ASSERT_NO_FATAL_FAILURE(expect_every_report_finite(out));
  EXPECT_FALSE(stream.tuning()[1].usable);
  EXPECT_GT(stream.tuning()[1].failed_candidates, 0);
  EXPECT_TRUE(stream.tuning()[0].usable && stream.tuning()[2].usable);
  ASSERT_EQ(stream.warnings().size(), 1u);
  EXPECT_NE(stream.warnings()[0].find("outcome 2"), std::string::npos) << stream.warnings()[0];
}

}  // namespace

}  // namespace causal::pipeline
