// The prognosis library against independent truth: closed forms for straight lines, noise-free ramps,
// coverage of the 90 % interval over many seeds of a noisy line, bounded influence of a spike, "unknown"
// and "reached", and checkpoints that continue bit for bit.
#include "causal/prognosis/channel_trends.hpp"
#include "causal/prognosis/degradation_trend.hpp"
#include "causal/prognosis/time_to_level.hpp"

#include "causal/estimation/state_archive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace causal::prognosis;

namespace {

constexpr std::int64_t kHour = 3600LL * 1000000000LL;
constexpr std::int64_t kT0 = 1704067200LL * 1000000000LL;

double phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// A trend fed y(t) = m0 + b t (+ noise) every 10 minutes for `hours`.
DegradationTrend ramp(double m0, double b, double hours, double noise_sd, std::mt19937_64* rng,
                      TrendParams params = {}) {
  DegradationTrend t(params);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i * (1.0 / 6.0) <= hours + 1e-9; ++i) {
    const double h = i / 6.0;
    const double y = m0 + b * h + (rng ? noise_sd * n(*rng) : 0.0);
    EXPECT_TRUE(t.observe(kT0 + static_cast<std::int64_t>(std::llround(h * kHour)), y, std::max(noise_sd, 0.01), false));
  }
  return t;
}

// The filter's model without the folded future acceleration, for straight lines and parabolas.
TrendParams no_forecast_diffusion() {
  TrendParams t;
  t.forecast_diffusion = 0.0;
  return t;
}

// No process noise at all: the forecast is the state's own Gaussian.
TrendParams no_diffusion() {
  TrendParams t;
  t.acceleration_diffusion = t.level_diffusion = 0.0;
  return t;
}

// Level, slope and acceleration, with independent standard deviations of level and slope (none elsewhere).
TrendState state_of(double level, double slope, double acceleration, double level_sd, double slope_sd) {
  TrendState s;
  s.x << level, slope, acceleration;
  s.p.setZero();
  s.p(0, 0) = level_sd * level_sd;
  s.p(1, 1) = slope_sd * slope_sd;
  return s;
}

// The Gaussian closed form alone: no pessimistic lower end.
PrognosisParams lenient() {
  PrognosisParams p;
  p.min_points_since_onset = 2;
  p.pessimistic_z = 0.0;
  return p;
}

}  // namespace

TEST(TimeToLevel, StraightLineClosedForm) {
  // q = 0: P(T <= t) = Phi((m + b t - L) / sqrt([1 t] P [1 t]^T)) exactly; the median is (L - m) / b.
  const TrendParams trend = no_diffusion();
  TrendState s = state_of(0.1, 0.02, 0.0, 0.01, 0.004);
  s.p(0, 1) = s.p(1, 0) = 0.3 * 0.01 * 0.004;
  const double l = std::log(2.0);
  const auto r = time_to_level(s, trend, l, 100, lenient());
  ASSERT_TRUE(r.known) << r.why;
  EXPECT_NEAR(r.hours, (l - 0.1) / 0.02, 1e-6);
  for (double t : {5.0, 20.0, 29.6, 40.0}) {
    const double sd = std::sqrt(s.p(0, 0) + 2 * t * s.p(0, 1) + t * t * s.p(1, 1));
    EXPECT_NEAR(crossing_probability(s, trend, l, t), phi((0.1 + 0.02 * t - l) / sd), 1e-9) << t;
  }
  // The interval bounds are the 5 % and 95 % points of that distribution.
  EXPECT_NEAR(crossing_probability(s, trend, l, r.hours_low), 0.05, 1e-6);
  EXPECT_NEAR(crossing_probability(s, trend, l, r.hours_high), 0.95, 1e-6);
}

TEST(TimeToLevel, NoiseFreeRampAndParabolaAreFollowed) {
  const double l = std::log(4.0);
  const auto line = ramp(0.0, 0.03, 24.0, 0.0, nullptr, no_forecast_diffusion());
  EXPECT_NEAR(line.state().x[1], 0.03, 1e-3);
  const auto r = time_to_level(line.state(), line.params(), l, 100, lenient());
  ASSERT_TRUE(r.known) << r.why;
  EXPECT_NEAR(r.hours, l / 0.03 - 24.0, 0.05 * (l / 0.03 - 24.0));
  // Accelerating: y = 0.002 t^2 reaches log 4 at sqrt(log4 / 0.002) = 26.3 h; observed for 15 h.
  DegradationTrend q(no_forecast_diffusion());
  for (int i = 0; i <= 90; ++i) {
    const double h = i / 6.0;
    ASSERT_TRUE(q.observe(kT0 + static_cast<std::int64_t>(std::llround(h * kHour)), 0.002 * h * h, 0.01, false));
  }
  const auto rq = time_to_level(q.state(), q.params(), l, 100, lenient());
  ASSERT_TRUE(rq.known) << rq.why;
  EXPECT_NEAR(rq.hours, std::sqrt(l / 0.002) - 15.0, 0.1 * (std::sqrt(l / 0.002) - 15.0));
  EXPECT_LE(rq.hours_low, std::sqrt(l / 0.002) - 15.0);
  EXPECT_GE(rq.hours_high, std::sqrt(l / 0.002) - 15.0);
}

TEST(TimeToLevel, IntervalCoversTheTruthOnNoisyLines) {
  // 300 seeds of a rising line with Gaussian noise, a decision after 48 h (the crossing is 21 h later): the
  // 90 % interval must hold the exact crossing time in about 90 % of them (binomial sd 1.7 %: 84-97 % accepted).
  // The filter's model made true: a constant acceleration (here 0), so almost no acceleration diffusion.
  const double l = std::log(4.0), b = 0.02, sd = 0.03;
  TrendParams model = no_forecast_diffusion();
  model.acceleration_diffusion = 1e-14;
  int known = 0, covered = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 rng(seed);
    const auto t = ramp(0.0, b, 48.0, sd, &rng, model);
    const auto r = time_to_level(t.state(), t.params(), l, 100, lenient());
    if (!r.known) continue;
    ++known;
    const double truth = l / b - 48.0;
    covered += r.hours_low <= truth && truth <= r.hours_high;
  }
  ASSERT_GT(known, 250);
  const double share = static_cast<double>(covered) / known;
  EXPECT_GT(share, 0.84) << covered << "/" << known;
  EXPECT_LT(share, 0.97) << covered << "/" << known;
}

TEST(TimeToLevel, PessimisticScenarioMovesOnlyTheLowerEnd) {
  // State with a rising slope and acceleration: the pessimistic lower end is the exponential path's closed form
  // m' + b' (exp(lambda s) - 1) / lambda = L, lambda = a' / b', every quantity at +z sd; median and upper end
  // stay those of the Gaussian forecast.
  const TrendParams trend = no_diffusion();
  TrendState s = state_of(0.1, 0.02, 0.0005, 0.01, 0.002);
  s.p(2, 2) = 0.0001 * 0.0001;
  const double l = std::log(4.0), z = 2.0;
  const auto gauss = time_to_level(s, trend, l, 100, lenient());
  PrognosisParams pessimistic = lenient();
  pessimistic.pessimistic_z = z;
  const auto r = time_to_level(s, trend, l, 100, pessimistic);
  ASSERT_TRUE(gauss.known && r.known) << gauss.why << r.why;
  EXPECT_EQ(r.hours, gauss.hours);
  EXPECT_EQ(r.hours_high, gauss.hours_high);
  const double m = 0.1 + z * 0.01, b = 0.02 + z * 0.002, a = 0.0005 + z * 0.0001, lambda = a / b;
  const double expected = std::log1p(lambda * (l - m) / b) / lambda;
  ASSERT_LT(expected, gauss.hours_low);  // the scenario is earlier here, so it is the lower end
  EXPECT_NEAR(r.hours_low, expected, 1e-9);
}

TEST(DegradationTrend, CalibrationInflatesOnlyWhenForecastsMiss) {
  // A steady noisy line: the model's 1-h forecasts hold, the inflation stays near 1. A line whose slope jumps
  // tenfold: the forecasts made an hour before miss by many sds, the inflation rises.
  std::mt19937_64 a(3), b(3);
  TrendParams calibrated;
  calibrated.calibration_lag_hours = 1.0;
  auto steady = ramp(0.0, 0.01, 48.0, 0.02, &a, calibrated);
  EXPECT_GT(steady.calibration_checks(), 40u);
  EXPECT_LT(steady.state().inflation, 2.0);
  auto jump = ramp(0.0, 0.01, 48.0, 0.02, &b, calibrated);
  std::normal_distribution<double> n(0.0, 1.0);
  const double y48 = 0.48;
  for (int i = 1; i <= 18; ++i) {
    const double h = i / 6.0;
    ASSERT_TRUE(jump.observe(jump.state().time_ns + kHour / 6, y48 + 0.1 * h + 0.02 * n(b), 0.02, false));
  }
  EXPECT_GT(jump.state().inflation, 2.0 * std::max(1.0, steady.state().inflation));
  // Off: no checks, no inflation.
  std::mt19937_64 c(3);
  TrendParams off;
  off.calibration_lag_hours = 0.0;
  auto plain = ramp(0.0, 0.01, 48.0, 0.02, &c, off);
  EXPECT_EQ(plain.calibration_checks(), 0u);
  EXPECT_EQ(plain.state().inflation, 1.0);
}

TEST(DegradationTrend, OneSpikeHasBoundedInfluence) {
  std::mt19937_64 a(7), b(7);
  auto clean = ramp(0.0, 0.01, 10.0, 0.02, &a);
  auto spiked = ramp(0.0, 0.01, 10.0, 0.02, &b);
  const std::int64_t t = clean.state().time_ns + kHour / 6;
  clean.observe(t, 0.1, 0.02, false);
  spiked.observe(t, 0.1 + 2.0, 0.02, false);  // a 7x spike in one snapshot
  EXPECT_EQ(spiked.downweighted(), clean.downweighted() + 1);
  const double s = std::sqrt(clean.state().p(0, 0) + 0.02 * 0.02);
  EXPECT_LT(spiked.state().x[0] - clean.state().x[0], 3.5 * s);  // moved as a 3-sigma innovation at most
  EXPECT_LT(spiked.state().x[1] - clean.state().x[1], 0.05);
}

TEST(TimeToLevel, UnknownAndReachedAreSaid) {
  std::mt19937_64 rng(3);
  const auto flat = ramp(0.0, 0.0, 24.0, 0.02, &rng);
  const auto r = time_to_level(flat.state(), flat.params(), std::log(2.0), 100, lenient());
  EXPECT_FALSE(r.known);
  EXPECT_TRUE(std::isnan(r.hours));
  EXPECT_NE(r.why.find("rising"), std::string::npos) << r.why;

  const auto line = ramp(0.0, 0.03, 24.0, 0.0, nullptr);
  PrognosisParams strict;
  strict.min_points_since_onset = 10;
  const auto early = time_to_level(line.state(), line.params(), std::log(4.0), 3, strict);
  EXPECT_FALSE(early.known);
  EXPECT_NE(early.why.find("too little data"), std::string::npos) << early.why;

  const auto reached = time_to_level(line.state(), line.params(), 0.5, 100, strict);  // 0.72 > 0.5 already
  EXPECT_TRUE(reached.known && reached.reached);
  EXPECT_EQ(reached.hours, 0.0);
}

TEST(DegradationTrend, LevelStepAtADiscontinuityIsNotASlope) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  DegradationTrend t;
  std::int64_t now = kT0;
  for (int i = 0; i < 300; ++i) {
    if (i == 150) now += 48 * kHour;  // two-day gap, then +18 % (a re-levelled plant)
    const double y = (i >= 150 ? std::log(1.18) : 0.0) + 0.015 * n(rng);
    ASSERT_TRUE(t.observe(now, y, 0.015, i == 150));
    now += kHour / 6;
  }
  const double z = t.state().x[1] / std::sqrt(t.state().p(1, 1));
  EXPECT_LT(z, 1.645) << "slope " << t.state().x[1];
}

TEST(ChannelTrends, RefusesCountsAndSkips) {
  ChannelTrends c(2, PrognosisParams{});
  Eigen::VectorXd y(2), noise(2);
  y << 0.1, NAN;
  noise << 0.01, 0.01;
  EXPECT_EQ(c.observe(kT0, y, noise, false), 0);  // NaN: no value now
  y << std::numeric_limits<double>::infinity(), 0.2;
  EXPECT_EQ(c.observe(kT0 + kHour, y, noise, false), 1);
  EXPECT_EQ(c.refused(), 1u);
  y << 0.1, 0.2;
  EXPECT_EQ(c.observe(kT0 + kHour, y, noise, false), 1);  // channel 0: time not after its last observation
  noise << 0.01, NAN;                                        // channel 1 without a baseline: not run
  EXPECT_EQ(c.observe(kT0 + 2 * kHour, y, noise, false), 0);
  EXPECT_EQ(c.trend(1).observations(), 1u);
}

TEST(ChannelTrends, CheckpointContinuesBitForBit) {
  const PrognosisParams params;
  ChannelTrends a(2, params);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  auto feed = [&](ChannelTrends& c, int from, int to) {
    for (int i = from; i < to; ++i) {
      Eigen::VectorXd y(2), noise(2);
      y << 0.002 * i + 0.02 * n(rng), 0.02 * n(rng);
      noise << 0.02, 0.02;
      c.observe(kT0 + i * kHour / 6, y, noise, i == 40);
    }
  };
  feed(a, 0, 100);
  causal::estimation::StateWriter w;
  a.save(w);
  causal::estimation::StateReader r(w.bytes());
  ChannelTrends b = ChannelTrends::restore(r, 2, params);
  EXPECT_TRUE(r.at_end());
  std::mt19937_64 keep = rng;
  feed(a, 100, 200);
  rng = keep;
  feed(b, 100, 200);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(a.trend(k).state().x, b.trend(k).state().x);
    EXPECT_EQ(a.trend(k).state().p, b.trend(k).state().p);
    EXPECT_EQ(a.trend(k).noise_scale(), b.trend(k).noise_scale());
  }
  // Other parameters or another channel count: refused.
  PrognosisParams other = params;
  other.trend.acceleration_diffusion *= 2;
  causal::estimation::StateReader r2(w.bytes());
  EXPECT_THROW(ChannelTrends::restore(r2, 2, other), causal::estimation::StateError);
  causal::estimation::StateReader r3(w.bytes());
  EXPECT_THROW(ChannelTrends::restore(r3, 3, params), causal::estimation::StateError);
}
