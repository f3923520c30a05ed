// causal::pipeline::FactorStream: the streaming wrapper must report exactly what the Kalman filter / fixed-lag
// smoother computes on the same samples, at the documented cadence, with per-sample times, whatever the
// framing; automatic noise must equal tune_noise_all on the calibration window and lose no sample.
#include "causal/pipeline/factor_stream.hpp"

#include "causal/estimation/batch_estimation.hpp"
#include "causal/estimation/noise_tuning.hpp"
#include "matrix_asserts.hpp"
#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::pipeline {
namespace {

using causal::test::ExpectedReport;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000LL;  // an epoch time in ns
constexpr double kPeriod = 50'000.0;                        // 20 kHz, exact in ns

estimation::ModelSpec spec(int g, int m, bool self_lags) {
  estimation::ModelSpec s;
  s.channels = g;
  s.lag_order = m;
  s.include_self_lags = self_lags;
  return s;
}

FactorStreamParams fixed_params(const estimation::ModelSpec& s, std::size_t publish_every, int fixed_lag = 0) {
  FactorStreamParams p;
  p.model = s;
  p.noise.automatic = false;
  p.noise.fixed = estimation::NoiseParams{2e-5, 0.05, 0.5};
  p.publish_every = publish_every;
  p.fixed_lag = fixed_lag;
  return p;
}

// Feeds y in irregular blocks; `disc_rows` start a block with discontinuity = true (row 0 always does).
// Block times are kT0 + first_row * kPeriod. Returns all reports including finish().
std::vector<FactorReport> feed_all(FactorStream& stream, const RowMajorMatrix& y,
                                   const std::vector<Eigen::Index>& sizes, const std::vector<bool>& disc_rows,
                                   bool finish = true) {
  std::vector<FactorReport> out;
  Eigen::Index at = 0;
  for (Eigen::Index s : sizes) {
    const bool d = !disc_rows.empty() && disc_rows[static_cast<std::size_t>(at)];
    stream.feed(y.middleRows(at, s), static_cast<std::uint64_t>(at), d, kT0 + static_cast<std::int64_t>(at) * 50'000, kPeriod, out);
    at += s;
  }
  if (finish) stream.finish(out);
  return out;
}

// y through a FactorStream publishing every `pe` with fixed lag `lag`, fed in irregular blocks; a new record starts
// at the first sample and at the first sample of block `restart_block`. The flags and the two kinds of report.
struct FixedLagRun {
  std::vector<bool> disc;
  std::vector<FactorReport> filt, smooth;
};
FixedLagRun run_fixed_lag(const estimation::SvarLayout& layout, const RowMajorMatrix& y, std::size_t pe, int lag,
                          std::size_t restart_block) {
  const auto sizes = causal::test::irregular_blocks(y.rows());
  FixedLagRun r;
  r.disc.assign(static_cast<std::size_t>(y.rows()), false);
  r.disc[0] = true;
  Eigen::Index restart = 0;
  for (std::size_t b = 0; b < restart_block; ++b) restart += sizes[b];
  r.disc[static_cast<std::size_t>(restart)] = true;
  FactorStream stream(fixed_params(layout.spec(), pe, lag));
  const auto all = feed_all(stream, y, sizes, r.disc);
  r.filt = causal::test::of_kind(all, EstimateKind::Filter);
  r.smooth = causal::test::of_kind(all, EstimateKind::FixedLag);
  return r;
}

void expect_report_matches(const FactorReport& r, const ExpectedReport& e, double tol) {
  SCOPED_TRACE("outcome " + std::to_string(e.outcome) + " at sample " + std::to_string(e.index));
  EXPECT_EQ(r.kind, EstimateKind::Filter);
  EXPECT_EQ(r.outcome, e.outcome);
  EXPECT_EQ(r.sample_index, e.index);
  EXPECT_MATRIX_NEAR(r.factors, e.factors, tol);
  EXPECT_MATRIX_NEAR(r.std_devs, e.std_devs, tol);
  EXPECT_EQ(r.innovation_count, e.innovation_count);
  EXPECT_TRUE(causal::test::same_or_both_nan(r.innovation_mean, e.innovation_mean, 1e-12))
      << r.innovation_mean << " vs " << e.innovation_mean;
  EXPECT_TRUE(causal::test::same_or_both_nan(r.nis_mean, e.nis_mean, 1e-12)) << r.nis_mean << " vs " << e.nis_mean;
  EXPECT_TRUE(causal::test::same_or_both_nan(r.last_innovation, e.last_innovation, 1e-12));
  EXPECT_TRUE(causal::test::same_or_both_nan(r.last_innovation_variance, e.last_innovation_variance, 1e-12));
  EXPECT_EQ(r.rejected, e.rejected);
}

struct FilterCase {
  int g, m;
  bool self_lags;
  int n;
  std::size_t publish_every;
};

class FactorStreamFilter : public ::testing::TestWithParam<FilterCase> {};

TEST_P(FactorStreamFilter, ReportsEqualTheFilterSteppedDirectly) {
  const FilterCase c = GetParam();
  const estimation::SvarLayout layout(spec(c.g, c.m, c.self_lags));
  const RowMajorMatrix y = causal::test::simulate_svar(layout, c.n, 1000 + static_cast<std::uint64_t>(c.g));
  FactorStream stream(fixed_params(layout.spec(), c.publish_every));
  const auto reports = feed_all(stream, y, causal::test::irregular_blocks(c.n), {});
  const auto expected = causal::test::reference_reports(layout, {estimation::NoiseParams{2e-5, 0.05, 0.5}}, y, {},
                                                        c.publish_every);
  // floor(N / publish_every) reports per outcome.
  ASSERT_EQ(reports.size(), static_cast<std::size_t>(c.n) / c.publish_every * static_cast<std::size_t>(c.g));
  ASSERT_EQ(reports.size(), expected.size());
  for (std::size_t i = 0; i < reports.size(); ++i) expect_report_matches(reports[i], expected[i], 1e-12);
  for (const auto& r : reports) {
    EXPECT_DOUBLE_EQ(r.q, 2e-5);
    EXPECT_DOUBLE_EQ(r.r, 0.05);
  }
  EXPECT_EQ(stream.samples_seen(), static_cast<std::uint64_t>(c.n));
  EXPECT_TRUE(stream.calibrated());
}

INSTANTIATE_TEST_SUITE_P(Models, FactorStreamFilter,
                         ::testing::Values(FilterCase{3, 1, false, 1000, 64}, FilterCase{4, 2, true, 777, 50},
                                           FilterCase{2, 1, false, 300, 1}, FilterCase{3, 3, true, 500, 499},
                                           FilterCase{3, 1, false, 40, 64}));

TEST(FactorStream, ReportCountIsFloorOfSamplesOverCadence) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  const RowMajorMatrix y = causal::test::simulate_svar(layout, 1000, 7);
  for (std::size_t pe : {1u, 2u, 3u, 10u, 64u, 999u, 1000u, 1001u}) {
    for (int n : {0, 1, 64, 65, 999, 1000}) {
      FactorStream stream(fixed_params(layout.spec(), pe));
      std::vector<FactorReport> out;
      stream.feed(y.topRows(n), 0, true, kT0, kPeriod, out);
      stream.finish(out);
      EXPECT_EQ(out.size(), static_cast<std::size_t>(n) / pe * 3) << "N=" << n << " publish_every=" << pe;
      for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].sample_index, (i / 3 + 1) * pe - 1);
        EXPECT_EQ(out[i].outcome, static_cast<int>(i % 3));
      }
    }
  }
}

TEST(FactorStream, ReportTimeIsFirstTimePlusIndexTimesPeriod) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  const int n = 900;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 11);
  FactorStream stream(fixed_params(layout.spec(), 37, 5));
  const auto reports = feed_all(stream, y, causal::test::irregular_blocks(n), {});
  ASSERT_FALSE(reports.empty());
  for (const auto& r : reports) {
    EXPECT_EQ(r.time_ns, kT0 + static_cast<std::int64_t>(r.sample_index) * 50'000) << "index " << r.sample_index;
  }
  // One block with a non-integer period (25.6 kHz): time = first + round(index * period).
  FactorStream one(fixed_params(layout.spec(), 37));
  std::vector<FactorReport> out;
  const double period = 1e9 / 25600.0;
  one.feed(y, 0, true, kT0, period, out);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(n / 37 * 3));
  for (const auto& r : out) {
    EXPECT_EQ(r.time_ns, kT0 + std::llround(static_cast<double>(r.sample_index) * period));
  }
}

TEST(FactorStream, DiscontinuitiesRestartLagsLikeTheFilter) {
  const estimation::SvarLayout layout(spec(3, 2, true));
  const int n = 1200;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 21);
  const auto sizes = causal::test::irregular_blocks(n);
  // Flag every third block start as a discontinuity.
  std::vector<bool> disc(static_cast<std::size_t>(n), false);
  Eigen::Index at = 0;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    if (b % 3 == 0) disc[static_cast<std::size_t>(at)] = true;
    at += sizes[b];
  }
  FactorStream stream(fixed_params(layout.spec(), 25));
  const auto reports = feed_all(stream, y, sizes, disc);
  const estimation::NoiseParams noise{2e-5, 0.05, 0.5};
  const auto expected = causal::test::reference_reports(layout, {noise}, y, disc, 25);
  ASSERT_EQ(reports.size(), expected.size());
  for (std::size_t i = 0; i < reports.size(); ++i) expect_report_matches(reports[i], expected[i], 1e-12);
  // The flags must have had an effect (otherwise the comparison above proves nothing about them).
  const auto no_flags = causal::test::reference_reports(layout, {noise}, y, {}, 25);
  EXPECT_GT((no_flags.back().factors - expected.back().factors).cwiseAbs().maxCoeff(), 1e-9);
  // Warm-up samples counted like the filter: M per discontinuity.
  estimation::SvarKalmanFilter direct(layout, {noise});
  for (Eigen::Index i = 0; i < n; ++i) direct.step(y.row(i).data(), disc[static_cast<std::size_t>(i)]);
  EXPECT_EQ(stream.counters().warm_up, direct.counters().warm_up);
  EXPECT_EQ(stream.counters().updated, direct.counters().updated);
}

TEST(FactorStream, NonFiniteSamplesAreRejectedAndCounted) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  const int n = 600;
  RowMajorMatrix y = causal::test::simulate_svar(layout, n, 31);
  for (int i : {10, 11, 200, 401, 402, 403}) y(i, i % 3) = std::numeric_limits<double>::quiet_NaN();
  y(300, 0) = std::numeric_limits<double>::infinity();
  FactorStream stream(fixed_params(layout.spec(), 100));
  const auto reports = feed_all(stream, y, causal::test::irregular_blocks(n), {});
  const auto expected = causal::test::reference_reports(layout, {estimation::NoiseParams{2e-5, 0.05, 0.5}}, y, {}, 100);
  ASSERT_EQ(reports.size(), expected.size());
  for (std::size_t i = 0; i < reports.size(); ++i) expect_report_matches(reports[i], expected[i], 1e-12);
  EXPECT_EQ(reports.back().rejected, 7u);
  EXPECT_EQ(stream.counters().rejected_non_finite, 7u);
}

TEST(FactorStream, FixedLagReportsEqualTheBatchFixedLagSmootherAtTheSameIndices) {
  const estimation::SvarLayout layout(spec(3, 1, true));
  const int n = 500, lag = 5;
  const std::size_t pe = 16;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 41);
  const FixedLagRun run = run_fixed_lag(layout, y, pe, lag, 3);  // a restart inside the record
  const auto& [disc, filt, smooth] = run;
  const std::size_t per_outcome = static_cast<std::size_t>(n) / pe;
  ASSERT_EQ(filt.size(), per_outcome * 3);
  ASSERT_EQ(smooth.size(), filt.size());  // after finish() every filter report has its twin

  const estimation::NoiseParams noise{2e-5, 0.05, 0.5};
  const estimation::EstimationRun batch =
      estimation::run_fixed_lag_smoother(layout, {noise}, Eigen::MatrixXd(y), disc, lag);
  for (std::size_t i = 0; i < smooth.size(); ++i) {
    const FactorReport& s = smooth[i];
    const FactorReport& f = filt[i];
    SCOPED_TRACE("fixed-lag report " + std::to_string(i));
    EXPECT_EQ(s.sample_index, f.sample_index);
    EXPECT_EQ(s.outcome, f.outcome);
    EXPECT_EQ(s.time_ns, f.time_ns);
    EXPECT_EQ(s.innovation_count, f.innovation_count);
    const auto row = static_cast<Eigen::Index>(s.sample_index);
    const auto off = layout.offset(s.outcome), d = layout.factor_count(s.outcome);
    EXPECT_MATRIX_NEAR(s.factors, batch.estimates.row(row).segment(off, d).transpose(), 1e-12);
    EXPECT_MATRIX_NEAR(s.std_devs, batch.std_devs.row(row).segment(off, d).transpose(), 1e-12);
  }
  // The smoother must actually differ from the filter somewhere (it uses later data).
  double diff = 0.0;
  for (std::size_t i = 0; i < smooth.size(); ++i) {
    diff = std::max(diff, (smooth[i].factors - filt[i].factors).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(diff, 1e-9);
}

TEST(FactorStream, FixedLagReportWaitsForItsLag) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  const int lag = 10;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, 200, 43);
  FactorStream stream(fixed_params(layout.spec(), 20, lag));
  std::vector<FactorReport> out;
  // Samples 0..28: filter report at 19, its twin needs sample 29.
  stream.feed(y.topRows(29), 0, true, kT0, kPeriod, out);
  EXPECT_EQ(causal::test::of_kind(out, EstimateKind::Filter).size(), 3u);
  EXPECT_EQ(causal::test::of_kind(out, EstimateKind::FixedLag).size(), 0u);
  stream.feed(y.middleRows(29, 1), 29, false, kT0 + 29 * 50'000, kPeriod, out);
  const auto smooth = causal::test::of_kind(out, EstimateKind::FixedLag);
  ASSERT_EQ(smooth.size(), 3u);
  for (const auto& s : smooth) {
    EXPECT_EQ(s.sample_index, 19u);
    EXPECT_EQ(s.time_ns, kT0 + 19 * 50'000);
  }
}

// Filter reports carry P_k: stepped here with a separate SvarKalmanFilter on the same samples and flags, the
// covariance at each report's sample must be the filter's covariance(k); fixed-lag reports carry none.
TEST(FactorStream, FilterReportsCarryTheFilterCovarianceBlock) {
  const estimation::SvarLayout layout(spec(3, 2, true));  // 2 + 3 + 3 = 8 factors per outcome
  const int n = 600, lag = 6;
  const std::size_t pe = 40;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 61);
  const FixedLagRun run = run_fixed_lag(layout, y, pe, lag, 4);
  const auto& [disc, filt, smooth] = run;
  ASSERT_EQ(filt.size(), static_cast<std::size_t>(n) / pe * 3);
  ASSERT_EQ(smooth.size(), filt.size());

  // Independent truth: the filter stepped directly, covariance(k) read at every publish point.
  estimation::SvarKalmanFilter direct(layout, {estimation::NoiseParams{2e-5, 0.05, 0.5}});
  std::vector<std::vector<Eigen::MatrixXd>> truth;  // per report time, per outcome
  for (Eigen::Index i = 0; i < n; ++i) {
    direct.step(y.row(i).data(), disc[static_cast<std::size_t>(i)]);
    if ((static_cast<std::size_t>(i) + 1) % pe != 0) continue;
    truth.emplace_back();
    for (int k = 0; k < 3; ++k) truth.back().push_back(direct.covariance(k));
  }
  ASSERT_EQ(truth.size() * 3, filt.size());
  double off_diagonal = 0.0;
  for (std::size_t i = 0; i < filt.size(); ++i) {
    const FactorReport& r = filt[i];
    SCOPED_TRACE("filter report " + std::to_string(i) + " (outcome " + std::to_string(r.outcome) + ")");
    const Eigen::MatrixXd& want = truth[i / 3][static_cast<std::size_t>(r.outcome)];
    ASSERT_EQ(r.covariance.rows(), layout.factor_count(r.outcome));
    ASSERT_EQ(r.covariance.cols(), layout.factor_count(r.outcome));
    EXPECT_MATRIX_NEAR(r.covariance, want, 1e-15);
    EXPECT_MATRIX_NEAR(r.covariance, r.covariance.transpose(), 1e-15 * r.covariance.cwiseAbs().maxCoeff());
    EXPECT_MATRIX_NEAR(r.covariance.diagonal().cwiseSqrt(), r.std_devs, 1e-14);
    EXPECT_SPD(r.covariance, 0.0);
    const Eigen::MatrixXd corr_free = r.covariance.diagonal().asDiagonal();
    off_diagonal = std::max(off_diagonal, (r.covariance - corr_free).cwiseAbs().maxCoeff());
  }
  // The blocks must actually carry correlations (otherwise std_devs would have said it all).
  EXPECT_GT(off_diagonal, 1e-6);
  for (const auto& s : smooth) EXPECT_EQ(s.covariance.size(), 0) << "fixed-lag report at " << s.sample_index;
}

// ---- automatic noise ------------------------------------------------------------------------------------

FactorStreamParams auto_params(const estimation::ModelSpec& s, std::size_t publish_every, std::size_t calibration,
                               int fixed_lag = 0) {
  FactorStreamParams p = fixed_params(s, publish_every, fixed_lag);
  p.noise.automatic = true;
  p.noise.fixed = estimation::NoiseParams{1e-3, 0.7, 0.5};  // configured values, far from the data's: tuning must replace them
  p.noise.calibration_samples = calibration;
  return p;
}

std::vector<estimation::NoiseParams> tuned_noise(const estimation::SvarLayout& layout, const RowMajorMatrix& window,
                                     const std::vector<bool>& disc, double p0) {
  estimation::NoiseTuningOptions options;
  options.p0 = p0;
  std::vector<estimation::NoiseParams> out;
  for (const auto& t : estimation::tune_noise_all(layout, Eigen::MatrixXd(window), disc, options)) out.push_back(t.noise);
  return out;
}

TEST(FactorStreamAutomatic, NoiseEqualsTuneNoiseAllAndNoSampleIsLost) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  const int n = 1000;
  const std::size_t cal = 400, pe = 64;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 51);
  std::vector<bool> disc(static_cast<std::size_t>(n), false);
  disc[0] = true;

  FactorStream stream(auto_params(layout.spec(), pe, cal));
  EXPECT_FALSE(stream.calibrated());
  std::vector<FactorReport> out;
  Eigen::Index at = 0;
  for (Eigen::Index s : causal::test::irregular_blocks(n)) {
    stream.feed(y.middleRows(at, s), static_cast<std::uint64_t>(at), at == 0, kT0 + static_cast<std::int64_t>(at) * 50'000, kPeriod, out);
    at += s;
    if (static_cast<std::size_t>(at) < cal) {
      EXPECT_FALSE(stream.calibrated()) << "after " << at << " samples";
      EXPECT_TRUE(out.empty()) << "nothing can be reported before the noise is known";
    } else {
      EXPECT_TRUE(stream.calibrated()) << "after " << at << " samples";
    }
  }
  stream.finish(out);

  // Same window, same flags, same p0: the stream's noise is tune_noise_all's.
  const std::vector<bool> cal_disc(disc.begin(), disc.begin() + static_cast<std::ptrdiff_t>(cal));
  const auto expected_noise = tuned_noise(layout, y.topRows(static_cast<Eigen::Index>(cal)), cal_disc, 0.5);
  ASSERT_EQ(stream.noise().size(), 3u);
  ASSERT_EQ(stream.tuning().size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const auto& got = stream.noise()[static_cast<std::size_t>(k)];
    const auto& want = expected_noise[static_cast<std::size_t>(k)];
    EXPECT_DOUBLE_EQ(got.q, want.q) << "outcome " << k;
    EXPECT_DOUBLE_EQ(got.r, want.r) << "outcome " << k;
    EXPECT_DOUBLE_EQ(got.p0, 0.5);
    EXPECT_GT(std::abs(std::log10(got.r / 0.7)), 0.3) << "tuned r should be far from the configured 0.7";
  }

  // No sample lost: the same report count as with fixed noise, and the reports are the filter run over ALL
  // samples (calibration window included) with the tuned noise.
  ASSERT_EQ(out.size(), static_cast<std::size_t>(n) / pe * 3);
  const auto expected = causal::test::reference_reports(layout, expected_noise, y, disc, pe);
  ASSERT_EQ(out.size(), expected.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    expect_report_matches(out[i], expected[i], 1e-12);
    EXPECT_EQ(out[i].time_ns, kT0 + static_cast<std::int64_t>(out[i].sample_index) * 50'000);
    EXPECT_DOUBLE_EQ(out[i].q, expected_noise[static_cast<std::size_t>(out[i].outcome)].q);
    EXPECT_DOUBLE_EQ(out[i].r, expected_noise[static_cast<std::size_t>(out[i].outcome)].r);
  }
  EXPECT_EQ(stream.samples_seen(), static_cast<std::uint64_t>(n));
}

TEST(FactorStreamAutomatic, FixedLagAfterCalibrationEqualsBatchSmootherWithTunedNoise) {
  const estimation::SvarLayout layout(spec(3, 1, true));
  const int n = 700, lag = 4;
  const std::size_t cal = 300, pe = 32;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 53);
  FactorStream stream(auto_params(layout.spec(), pe, cal, lag));
  std::vector<bool> disc(static_cast<std::size_t>(n), false);
  disc[0] = true;
  const auto all = feed_all(stream, y, causal::test::irregular_blocks(n), disc);
  const auto noise = tuned_noise(layout, y.topRows(static_cast<Eigen::Index>(cal)),
                                 std::vector<bool>(disc.begin(), disc.begin() + static_cast<std::ptrdiff_t>(cal)), 0.5);
  const auto smooth = causal::test::of_kind(all, EstimateKind::FixedLag);
  ASSERT_EQ(smooth.size(), static_cast<std::size_t>(n) / pe * 3);
  const estimation::EstimationRun batch = estimation::run_fixed_lag_smoother(layout, noise, Eigen::MatrixXd(y), disc, lag);
  for (const auto& s : smooth) {
    const auto row = static_cast<Eigen::Index>(s.sample_index);
    EXPECT_MATRIX_NEAR(s.factors, batch.estimates.row(row).segment(layout.offset(s.outcome),
                                                                   layout.factor_count(s.outcome)).transpose(), 1e-12);
  }
}

TEST(FactorStreamAutomatic, FinishCalibratesOnWhatWasBuffered) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  const int n = 300;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 57);
  FactorStream stream(auto_params(layout.spec(), 64, 400));
  std::vector<FactorReport> out;
  stream.feed(y, 0, true, kT0, kPeriod, out);
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(stream.calibrated());
  stream.finish(out);
  EXPECT_TRUE(stream.calibrated());
  std::vector<bool> disc(static_cast<std::size_t>(n), false);
  disc[0] = true;
  const auto noise = tuned_noise(layout, y, disc, 0.5);
  const auto expected = causal::test::reference_reports(layout, noise, y, disc, 64);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(n) / 64 * 3);
  ASSERT_EQ(out.size(), expected.size());
  for (std::size_t i = 0; i < out.size(); ++i) expect_report_matches(out[i], expected[i], 1e-12);
}

TEST(FactorStreamAutomatic, FinishOnAnEmptyStreamReportsNothing) {
  const estimation::SvarLayout layout(spec(3, 1, false));
  FactorStream stream(auto_params(layout.spec(), 64, 400));
  std::vector<FactorReport> out;
  stream.finish(out);
  EXPECT_TRUE(out.empty());
}

// factor_stream.cpp, calibrate(): "A window with too few usable samples cannot be tuned: keep the configured
// values for that outcome." tune_noise documents that case as converged = false with NoiseParams{} (the
// library defaults, not the configured values) and updates = the (too few, but > 0) usable count.
TEST(FactorStreamAutomatic, TooFewUsableSamplesKeepsTheConfiguredNoise) {
  const estimation::SvarLayout layout(spec(3, 1, false));  // 4 factors per outcome: tuning needs >= 2*4 + 10 = 18 updates
  const RowMajorMatrix y = causal::test::simulate_svar(layout, 15, 59);
  FactorStream stream(auto_params(layout.spec(), 5, 400));
  std::vector<FactorReport> out;
  stream.feed(y, 0, true, kT0, kPeriod, out);
  stream.finish(out);
  ASSERT_TRUE(stream.calibrated());
  ASSERT_EQ(stream.tuning().size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const auto& t = stream.tuning()[static_cast<std::size_t>(k)];
    EXPECT_FALSE(t.converged);
    EXPECT_LT(t.updates, 18);
    const auto& n = stream.noise()[static_cast<std::size_t>(k)];
    EXPECT_DOUBLE_EQ(n.q, 1e-3) << "outcome " << k << ": configured q must be kept";
    EXPECT_DOUBLE_EQ(n.r, 0.7) << "outcome " << k << ": configured r must be kept";
  }
  ASSERT_EQ(out.size(), 3u * 3u);
  for (const auto& r : out) EXPECT_DOUBLE_EQ(r.r, 0.7);
}

// ---- parameter and shape errors ----------------------------------------------------------------------------

TEST(FactorStream, InvalidParametersThrow) {
  const estimation::ModelSpec s = spec(3, 1, false);
  auto p = fixed_params(s, 0);
  EXPECT_THROW(FactorStream{p}, std::invalid_argument);
  p = fixed_params(s, 10, -1);
  EXPECT_THROW(FactorStream{p}, std::invalid_argument);
  p = fixed_params(s, 10);
  p.noise.fixed.r = 0.0;
  EXPECT_THROW(FactorStream{p}, std::invalid_argument);
  p = fixed_params(s, 10);
  p.noise.fixed.q = -1e-6;
  EXPECT_THROW(FactorStream{p}, std::invalid_argument);
  p = fixed_params(spec(1, 1, false), 10);
  EXPECT_THROW(FactorStream{p}, std::invalid_argument);
  // Automatic: at least 10 x factors per outcome + 10 calibration samples (4 factors here: 50).
  EXPECT_THROW(FactorStream{auto_params(s, 10, 49)}, std::invalid_argument);
  EXPECT_NO_THROW(FactorStream{auto_params(s, 10, 50)});
}

TEST(FactorStream, BlockWithWrongChannelCountThrows) {
  FactorStream stream(fixed_params(spec(3, 1, false), 10));
  std::vector<FactorReport> out;
  const RowMajorMatrix four = RowMajorMatrix::Ones(5, 4);
  EXPECT_THROW(stream.feed(four, 0, true, kT0, kPeriod, out), std::invalid_argument);
  EXPECT_EQ(stream.samples_seen(), 0u);
}

}  // namespace

}  // namespace causal::pipeline
