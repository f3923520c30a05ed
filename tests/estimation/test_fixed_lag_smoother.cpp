// FixedLagSmoother: x[n | n+L] must equal RTS run on data[0..n+L] at index n (streaming and batch forms).
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <stdexcept>

#include "causal/estimation/batch_estimation.hpp"
#include "causal/estimation/fixed_lag_smoother.hpp"
#include "causal/estimation/state_archive.hpp"
#include "matrix_asserts.hpp"
#include "svar_test_support.hpp"

namespace causal {
namespace {

using test::spec_g;

struct Case {
  int g, m, lag, n;
};

class FixedLagEqualsRts : public ::testing::TestWithParam<Case> {};

TEST_P(FixedLagEqualsRts, StreamingAndBatch) {
  const Case c = GetParam();
  estimation::SvarLayout layout(spec_g(c.g, c.m));
  const std::vector<estimation::NoiseParams> noise = {{1e-3, 0.05, 1.0}};
  test::Simulation sim = test::simulate_svar(layout, noise, c.n, 100 + c.lag, 0.1);
  std::vector<bool> disc(c.n, false);
  disc[c.n / 2] = true;
  sim.y(c.n / 4, 0) = std::numeric_limits<double>::quiet_NaN();

  estimation::FixedLagSmoother smoother(layout, noise, c.lag);
  const estimation::EstimationRun batch = estimation::run_fixed_lag_smoother(layout, noise, sim.y, disc, c.lag);
  int released = 0;
  for (int n = 0; n < c.n; ++n) {
    const Eigen::RowVectorXd row = sim.y.row(n);
    const auto out = smoother.step(row.data(), disc[n]);
    if (n < c.lag) {
      ASSERT_FALSE(out.has_value());
      continue;
    }
    ASSERT_TRUE(out.has_value());
    const int idx = n - c.lag;
    ASSERT_EQ(out->index, static_cast<std::uint64_t>(idx));
    ++released;
    // Truth: RTS over the prefix data[0..n], read at idx.
    const std::vector<bool> prefix_disc(disc.begin(), disc.begin() + n + 1);
    const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, sim.y.topRows(n + 1), prefix_disc);
    ASSERT_MATRIX_NEAR(out->estimates, rts.estimates.row(idx).transpose(), 1e-9) << "n = " << n;
    ASSERT_MATRIX_NEAR(out->std_devs, rts.std_devs.row(idx).transpose(), 1e-9) << "n = " << n;
    ASSERT_MATRIX_NEAR(batch.estimates.row(idx), rts.estimates.row(idx), 1e-9);
  }
  // End of stream: the remaining samples use all data, i.e. equal full RTS.
  const estimation::EstimationRun full = estimation::run_rts_smoother(layout, noise, sim.y, disc);
  const auto rest = smoother.flush();
  ASSERT_EQ(static_cast<int>(rest.size()), std::min(c.lag, c.n));
  for (const estimation::SmoothedSample& s : rest) {
    const auto idx = static_cast<Eigen::Index>(s.index);
    ++released;
    ASSERT_MATRIX_NEAR(s.estimates, full.estimates.row(idx).transpose(), 1e-9);
    ASSERT_MATRIX_NEAR(s.std_devs, full.std_devs.row(idx).transpose(), 1e-9);
    ASSERT_MATRIX_NEAR(batch.estimates.row(idx), full.estimates.row(idx), 1e-12);
    ASSERT_MATRIX_NEAR(batch.std_devs.row(idx), full.std_devs.row(idx), 1e-9);
  }
  EXPECT_EQ(released, c.n);
  EXPECT_EQ(smoother.filter().counters().rejected_non_finite, 1u);
}

INSTANTIATE_TEST_SUITE_P(Cases, FixedLagEqualsRts,
                         ::testing::Values(Case{4, 1, 10, 200}, Case{3, 2, 25, 160}, Case{2, 1, 1, 60},
                                           Case{5, 3, 4, 80} /* 16 factors: generic-size path */));

// Masked model: lane groups of different dimensions and an outcome without factors.
TEST(FixedLagSmoother, MaskedModelEqualsRtsOnPrefix) {
  estimation::ModelSpec spec = spec_g(4, 1);
  spec.allowed = {{true, false, false, false}, {true, true, true, true}, {true, true, true, false},
                  {true, true, true, true}};
  estimation::SvarLayout layout(spec);
  ASSERT_EQ(layout.factor_count(0), 0);
  const std::vector<estimation::NoiseParams> noise = {{1e-3, 0.05, 1.0}, {2e-3, 0.02, 1.0}, {5e-4, 0.05, 2.0}, {1e-3, 0.1, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 90, 12, 0.1);
  const int lag = 6;
  estimation::FixedLagSmoother smoother(layout, noise, lag);
  for (int n = 0; n < 90; ++n) {
    const Eigen::RowVectorXd row = sim.y.row(n);
    const auto out = smoother.step(row.data());
    if (!out) continue;
    const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, sim.y.topRows(n + 1));
    ASSERT_MATRIX_NEAR(out->estimates, rts.estimates.row(n - lag).transpose(), 1e-9) << "n = " << n;
    ASSERT_MATRIX_NEAR(out->std_devs, rts.std_devs.row(n - lag).transpose(), 1e-9) << "n = " << n;
  }
  const estimation::EstimationRun batch = estimation::run_fixed_lag_smoother(layout, noise, sim.y, {}, lag);
  EXPECT_TRUE(batch.innovations.col(0).tail(80).isApprox(sim.y.col(0).tail(80)));  // no factors: e = y
  EXPECT_TRUE((batch.innovation_variances.col(0).tail(80).array() == 0.05).all());
}

TEST(FixedLagSmoother, LagZeroIsTheFilter) {
  estimation::SvarLayout layout(spec_g(4, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-3, 0.05, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 100, 5);
  const estimation::EstimationRun filt = estimation::run_filter(layout, noise, sim.y);
  estimation::FixedLagSmoother smoother(layout, noise, 0);
  for (int n = 0; n < 100; ++n) {
    const Eigen::RowVectorXd row = sim.y.row(n);
    const auto out = smoother.step(row.data());
    ASSERT_TRUE(out.has_value());
    ASSERT_EQ(out->index, static_cast<std::uint64_t>(n));
    ASSERT_MATRIX_NEAR(out->estimates, filt.estimates.row(n).transpose(), 1e-13);
    ASSERT_MATRIX_NEAR(out->std_devs, filt.std_devs.row(n).transpose(), 1e-13);
  }
  EXPECT_TRUE(smoother.flush().empty());
}

TEST(FixedLagSmoother, FlushedIndicesAreNeverReleasedTwice) {
  estimation::SvarLayout layout(spec_g(3, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-3, 0.05, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 40, 6);
  estimation::FixedLagSmoother smoother(layout, noise, 5);
  std::vector<std::uint64_t> indices;
  auto feed = [&](int from, int to) {
    for (int n = from; n < to; ++n) {
      const Eigen::RowVectorXd row = sim.y.row(n);
      if (auto out = smoother.step(row.data())) indices.push_back(out->index);
    }
  };
  feed(0, 20);
  for (const auto& s : smoother.flush()) indices.push_back(s.index);
  feed(20, 40);
  for (const auto& s : smoother.flush()) indices.push_back(s.index);
  ASSERT_EQ(indices.size(), 40u);
  for (std::size_t i = 0; i < indices.size(); ++i) EXPECT_EQ(indices[i], i);
}

TEST(FixedLagSmoother, StepIntoMatchesStepAndNegativeLagThrows) {
  estimation::SvarLayout layout(spec_g(3, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-3, 0.05, 1.0}};
  const test::Simulation sim = test::simulate_svar(layout, noise, 30, 8);
  estimation::FixedLagSmoother a(layout, noise, 3), b(layout, noise, 3);
  Eigen::VectorXd est(layout.total_factors()), sd(layout.total_factors());
  for (int n = 0; n < 30; ++n) {
    const Eigen::RowVectorXd row = sim.y.row(n);
    std::uint64_t idx = 0;
    const bool got = a.step_into(row.data(), false, &idx, est.data(), sd.data());
    const auto out = b.step(row.data());
    ASSERT_EQ(got, out.has_value());
    if (got) {
      EXPECT_EQ(idx, out->index);
      ASSERT_MATRIX_NEAR(est, out->estimates, 0.0);
      ASSERT_MATRIX_NEAR(sd, out->std_devs, 0.0);
    }
  }
  EXPECT_EQ(a.last_status(), estimation::SampleStatus::Updated);
  EXPECT_THROW(estimation::FixedLagSmoother(layout, noise, -1), std::invalid_argument);
  EXPECT_THROW(estimation::FixedLagSmoother(layout, noise, 3, 0), std::invalid_argument);
}

// Decimation: only indices with (index + 1) % m == 0 are released, each equal to RTS on the data up to its
// release (the same truth as the full smoother), for m below, equal to and above the lag, with a gap and a
// rejected sample in the stream; flush releases the remaining decimated indices with all the data.
TEST(FixedLagSmoother, DecimatedReleasesEqualRtsAtTheReleasedIndices) {
  estimation::SvarLayout layout(spec_g(4, 1));
  const std::vector<estimation::NoiseParams> noise = {{1e-3, 0.05, 1.0}};
  constexpr int kN = 150, kLag = 8;
  test::Simulation sim = test::simulate_svar(layout, noise, kN, 77, 0.1);
  std::vector<bool> disc(kN, false);
  disc[61] = true;
  sim.y(40, 2) = std::numeric_limits<double>::quiet_NaN();
  const estimation::EstimationRun full = estimation::run_rts_smoother(layout, noise, sim.y, disc);
  for (const std::uint64_t m : {3u, 8u, 20u}) {
    estimation::FixedLagSmoother smoother(layout, noise, kLag, m);
    std::vector<std::uint64_t> got;
    for (int n = 0; n < kN; ++n) {
      const Eigen::RowVectorXd row = sim.y.row(n);
      const auto out = smoother.step(row.data(), disc[n]);
      if (!out) continue;
      ASSERT_EQ(out->index + kLag, static_cast<std::uint64_t>(n)) << "m = " << m;
      got.push_back(out->index);
      const std::vector<bool> prefix_disc(disc.begin(), disc.begin() + n + 1);
      const estimation::EstimationRun rts = estimation::run_rts_smoother(layout, noise, sim.y.topRows(n + 1), prefix_disc);
      const auto idx = static_cast<Eigen::Index>(out->index);
      ASSERT_MATRIX_NEAR(out->estimates, rts.estimates.row(idx).transpose(), 1e-9) << "m = " << m << ", n = " << n;
      ASSERT_MATRIX_NEAR(out->std_devs, rts.std_devs.row(idx).transpose(), 1e-9) << "m = " << m << ", n = " << n;
    }
    for (const estimation::SmoothedSample& s : smoother.flush()) {
      got.push_back(s.index);
      const auto idx = static_cast<Eigen::Index>(s.index);
      ASSERT_MATRIX_NEAR(s.estimates, full.estimates.row(idx).transpose(), 1e-9) << "m = " << m;
      ASSERT_MATRIX_NEAR(s.std_devs, full.std_devs.row(idx).transpose(), 1e-9) << "m = " << m;
    }
    std::vector<std::uint64_t> want;
    for (std::uint64_t i = m - 1; i < static_cast<std::uint64_t>(kN); i += m) want.push_back(i);
    EXPECT_EQ(got, want) << "m = " << m;
  }
}

// Checkpoint: smoother + filter restored into a fresh smoother continue bit for bit (every released sample
// and the final flush), for cuts before the lag is full, at a release, and with decimation; another lag or
// decimation throws.
TEST(FixedLagSmootherCheckpoint, RestoredSmootherContinuesBitForBit) {
  const estimation::SvarLayout layout(spec_g(3, 1));
  const std::vector<estimation::NoiseParams> noise{estimation::NoiseParams{1e-4, 0.05, 0.5}};
  const auto sim = test::simulate_svar(layout, noise, 90, 12);
  std::vector<bool> disc(90, false);
  disc[0] = disc[50] = true;
  auto same = [](const estimation::SmoothedSample& a, const estimation::SmoothedSample& b) {
    const auto bytes = sizeof(double) * static_cast<std::size_t>(a.estimates.size());
    return a.index == b.index && a.estimates.size() == b.estimates.size() &&
           std::memcmp(a.estimates.data(), b.estimates.data(), bytes) == 0 &&
           std::memcmp(a.std_devs.data(), b.std_devs.data(), bytes) == 0;
  };
  for (const std::uint64_t m : {1u, 4u}) {
    for (int cut : {0, 3, 7, 8, 9, 31, 50, 89}) {
      SCOPED_TRACE("release_every " + std::to_string(m) + ", cut at " + std::to_string(cut));
      estimation::FixedLagSmoother whole(layout, noise, 8, m), first(layout, noise, 8, m);
      for (int n = 0; n < cut; ++n) {
        const Eigen::RowVectorXd row = sim.y.row(n);
        whole.step(row.data(), disc[n]);
        first.step(row.data(), disc[n]);
      }
      estimation::StateWriter w;
      first.save(w);
      estimation::FixedLagSmoother restored(layout, noise, 8, m);
      estimation::StateReader r(w.bytes());
      restored.restore(r);
      EXPECT_TRUE(r.at_end());
      for (int n = cut; n < 90; ++n) {
        const Eigen::RowVectorXd row = sim.y.row(n);
        const auto a = restored.step(row.data(), disc[n]);
        const auto b = whole.step(row.data(), disc[n]);
        ASSERT_EQ(a.has_value(), b.has_value()) << "sample " << n;
        if (a) {
          ASSERT_TRUE(same(*a, *b)) << "sample " << n;
        }
      }
      const auto fa = restored.flush(), fb = whole.flush();
      ASSERT_EQ(fa.size(), fb.size());
      for (std::size_t i = 0; i < fa.size(); ++i) EXPECT_TRUE(same(fa[i], fb[i])) << "flushed " << i;
    }
  }
  estimation::FixedLagSmoother saved(layout, noise, 8, 4);
  estimation::StateWriter w;
  saved.save(w);
  estimation::FixedLagSmoother other_lag(layout, noise, 6, 4), other_m(layout, noise, 8, 1);
  estimation::StateReader r1(w.bytes()), r2(w.bytes());
  EXPECT_THROW(other_lag.restore(r1), estimation::StateError);
  EXPECT_THROW(other_m.restore(r2), estimation::StateError);
}

}  // namespace
}  // namespace causal
