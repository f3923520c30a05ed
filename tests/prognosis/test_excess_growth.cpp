// The excess-growth forecast (excess_growth.hpp) against independent truth: the straight line of ln w in closed
// form, the defective first passage of a falling drift, coverage of the 90 % interval over many seeds of the
// model itself, "too few hours" and "reached", and the channel trends' level history through a checkpoint.
#include "causal/prognosis/channel_trends.hpp"
#include "causal/prognosis/excess_growth.hpp"

#include "causal/estimation/state_archive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace causal::prognosis;

namespace {

constexpr std::int64_t kHour = 3600LL * 1000000000LL;
constexpr std::int64_t kT0 = 1704067200LL * 1000000000LL;

// Log excess w(t) = exp(z(t)) every 10 minutes for `hours`, z a Wiener process with drift mu and diffusion
// sigma2 per hour from z0 (sigma2 = 0: a straight line of ln w).
void excess_path(double z0, double mu, double sigma2, double hours, std::mt19937_64& rng, std::vector<double>& t,
                 std::vector<double>& w) {
  std::normal_distribution<double> n(0.0, 1.0);
  double z = z0;
  for (int i = 0; i * (1.0 / 6.0) <= hours + 1e-9; ++i) {
    if (i > 0) z += mu / 6.0 + std::sqrt(sigma2 / 6.0) * n(rng);
    t.push_back(i / 6.0);
    w.push_back(std::exp(z));
  }
}

// The exponential-excess shape alone (the Wiener process in time whose closed forms the tests check).
PrognosisParams straight() {
  PrognosisParams p;
  p.excess.power_law = false;
  return p;
}

}  // namespace

TEST(ExcessGrowth, StraightLogExcessInClosedForm) {
  // ln w = ln 0.1 + 0.05 t over 20 h, noise-free: the time to ln w = ln(ln 4) is (ln ln 4 - ln w(now)) / 0.05.
  std::mt19937_64 rng(1);
  std::vector<double> t, w;
  excess_path(std::log(0.1), 0.05, 0.0, 20.0, rng, t, w);
  const TimeToLevel out = excess_growth_time_to(t, w, 0.01, std::log(4.0), straight());
  ASSERT_TRUE(out.known) << out.why;
  const double expected = (std::log(std::log(4.0)) - (std::log(0.1) + 0.05 * 20.0)) / 0.05;
  EXPECT_NEAR(out.hours, expected, 0.01 * expected);
  EXPECT_LE(out.hours_low, out.hours);
  EXPECT_GE(out.hours_high, out.hours);
}

TEST(ExcessGrowth, LinearExcessIsAPowerLawAndCrossesOnTime) {
  // w = 0.05 tau (a power law of exponent 1), noise-free, 12 h since the onset: w reaches ln 4 at
  // tau = ln 4 / 0.05 = 27.7 h, 15.7 h from now. The exponential shape alone would say much earlier.
  std::vector<double> t, w;
  for (int i = 1; i <= 72; ++i) {
    t.push_back(i / 6.0);
    w.push_back(0.05 * i / 6.0);
  }
  const TimeToLevel both = excess_growth_time_to(t, w, 0.001, std::log(4.0), PrognosisParams{});
  ASSERT_TRUE(both.known) << both.why;
  const double expected = std::log(4.0) / 0.05 - 12.0;
  EXPECT_NEAR(both.hours, expected, 0.02 * expected);
  const TimeToLevel exponential = excess_growth_time_to(t, w, 0.001, std::log(4.0), straight());
  ASSERT_TRUE(exponential.known) << exponential.why;
  EXPECT_LT(exponential.hours, 0.8 * expected);
}

TEST(ExcessGrowth, FallingDriftNeverCrossesWithTheDefectiveProbability) {
  // A Wiener process with drift -0.1 and variance 0.04 per hour crosses a gap of 0.5 with probability
  // exp(2 mu g / sigma^2) = exp(-2.5) at all (Chhikara and Folks 1989).
  EXPECT_NEAR(excess_passage_probability(0.5, -0.1, 0.0, 0.04, 1e6), std::exp(-2.5), 1e-6);
  EXPECT_NEAR(excess_passage_probability(0.5, 0.1, 0.0, 0.04, 1e6), 1.0, 1e-9);
  // The mean passage time g / mu: P(T <= g / mu) of an inverse Gaussian of mean 5 h and shape 6.25 h.
  const double m = 5.0, shape = 0.25 / 0.04, tt = 5.0;
  const double ig = 0.5 * std::erfc(-std::sqrt(shape / tt) * (tt / m - 1) / std::sqrt(2.0)) +
                    std::exp(2 * shape / m) * 0.5 * std::erfc(std::sqrt(shape / tt) * (tt / m + 1) / std::sqrt(2.0));
  EXPECT_NEAR(excess_passage_probability(0.5, 0.1, 0.0, 0.04, tt), ig, 1e-9);
}

TEST(ExcessGrowth, NinetyPercentIntervalsCoverTheModelsOwnPaths) {
  // 300 paths of the model (drift 0.04 / h, diffusion 0.004 / h): forecast at 24 h, the path continued until
  // ln w reaches ln(ln 4); the 90 % interval must hold that time in about 90 % of the paths.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  int known = 0, covered = 0;
  for (int run = 0; run < 300; ++run) {
    std::vector<double> t, w;
    excess_path(std::log(0.15), 0.04, 0.004, 24.0, rng, t, w);
    const TimeToLevel out = excess_growth_time_to(t, w, 0.01, std::log(4.0), straight());
    double z = std::log(w.back()), h = 0.0;
    while (z < std::log(std::log(4.0)) && h < 2000) {
      z += 0.04 / 6.0 + std::sqrt(0.004 / 6.0) * n(rng);
      h += 1.0 / 6.0;
    }
    if (!out.known) continue;
    ++known;
    if (out.hours_low <= h && h <= out.hours_high) ++covered;
  }
  ASSERT_GE(known, 200);  // the rest: no significant drift yet, or wider than a factor of 10 (unknown)
  const double coverage = static_cast<double>(covered) / known;
  EXPECT_GT(coverage, 0.84) << known;
  EXPECT_LT(coverage, 0.96);
}

TEST(ExcessGrowth, TooFewHoursAboveTheNoiseAndReached) {
  std::mt19937_64 rng(3);
  std::vector<double> t, w;
  excess_path(std::log(0.01), 0.0, 0.0, 10.0, rng, t, w);  // w = 0.01: below 3 x 0.02
  bool too_little = false;
  TimeToLevel out = excess_growth_time_to(t, w, 0.02, std::log(2.0), straight(), &too_little);
  EXPECT_FALSE(out.known);
  EXPECT_TRUE(too_little);
  EXPECT_NE(out.why.find("too few hours"), std::string::npos) << out.why;
  t.clear();
  w.clear();
  excess_path(std::log(0.8), 0.0, 0.0, 10.0, rng, t, w);  // the last hour's median at ln 2.2 > ln 2
  out = excess_growth_time_to(t, w, 0.02, std::log(2.0), straight(), &too_little);
  EXPECT_TRUE(out.known && out.reached);
  EXPECT_FALSE(too_little);
}

TEST(ExcessGrowth, ChannelTrendsKeepTheHistoryThroughACheckpoint) {
  PrognosisParams params = straight();
  params.history_limit = 50;
  ChannelTrends a(1, params);
  Eigen::VectorXd y(1), noise(1);
  noise << 0.01;
  for (int i = 0; i < 80; ++i) {
    y << std::log(0.06) + (i < 20 ? 0.0 : std::exp(std::log(0.1) + 0.05 * (i - 20) / 6.0));
    a.observe(kT0 + i * kHour / 6, y, noise, false);
  }
  ASSERT_EQ(a.history(0).size(), 50u);  // bounded: the oldest dropped
  EXPECT_EQ(a.history(0).front().time_ns, kT0 + 30 * kHour / 6);
  causal::estimation::StateWriter out;
  a.save(out);
  causal::estimation::StateReader in(out.bytes());
  const ChannelTrends b = ChannelTrends::restore(in, 1, params);
  EXPECT_TRUE(in.at_end());
  const TimeToLevel ta = a.time_to(0, std::log(0.06), 4.0, 60, kT0 + 20 * kHour / 6, 0.01);
  const TimeToLevel tb = b.time_to(0, std::log(0.06), 4.0, 60, kT0 + 20 * kHour / 6, 0.01);
  ASSERT_TRUE(ta.known) << ta.why;
  EXPECT_EQ(ta.hours, tb.hours);
  EXPECT_EQ(ta.hours_high, tb.hours_high);
  PrognosisParams other = params;
  other.history_limit = 60;
  causal::estimation::StateReader in2(out.bytes());
  EXPECT_THROW(ChannelTrends::restore(in2, 1, other), causal::estimation::StateError);
}
