// StructuredFactorStream checkpoints: cut before the structure calibration window is full (the window is
// in the checkpoint), at its end, and after it (the learned centre, causal order and restricted model are),
// save, restore into a FRESH stream, feed the rest: reports and learned structure equal the uninterrupted
// run bit for bit. Also with both windows in a row (structure, then automatic noise). Other settings throw.
#include "causal/pipeline/structured_factor_stream.hpp"

#include "checkpoint_test_util.hpp"
#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace causal::pipeline {
namespace {

using causal::test::checkpoint_of;
using causal::test::expect_identical;
using causal::test::restore_from;
using causal::test::same_bits;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000LL;
constexpr double kPeriod = 600e9;
constexpr std::uint64_t kFirstSnapshot = 400;

// The shipped condition level: self lags, fixed noise, one report per vector, fixed lag 6, centre + LiNGAM
// on the first 100 vectors.
FactorStreamParams condition_params() {
  FactorStreamParams p;
  p.model.channels = 4;
  p.model.lag_order = 1;
  p.model.include_self_lags = true;
  p.noise.fixed = estimation::NoiseParams{1e-4, 1e-2, 1.0};
  p.publish_every = 1;
  p.fixed_lag = 6;
  return p;
}

StructureSetting learn_all(std::size_t window) {
  StructureSetting s;
  s.calibration_samples = window;
  s.centre = true;
  s.learn_order = true;
  return s;
}

RowMajorMatrix series(int n) {
  RowMajorMatrix y = causal::test::simulate_lingam(n, 17, 0.3, -2.5);
  y(120, 2) = std::numeric_limits<double>::quiet_NaN();  // a rejected vector after the window
  return y;
}

void feed_rows(StructuredFactorStream& s, const RowMajorMatrix& y, Eigen::Index from, Eigen::Index to,
               std::vector<FactorReport>& out) {
  auto disc = [](Eigen::Index row) { return row == 0 || row == 200; };  // a restart of the series at 200
  Eigen::Index at = from;
  for (Eigen::Index b : causal::test::irregular_blocks(to - from)) {
    const Eigen::Index end = at + b;
    while (at < end) {  // split blocks at a discontinuity (the flag applies to a block's row 0)
      Eigen::Index m = 1;
      while (at + m < end && !disc(at + m)) ++m;
      s.feed(y.middleRows(at, m), kFirstSnapshot + static_cast<std::uint64_t>(at), disc(at),
             kT0 + static_cast<std::int64_t>(static_cast<double>(at) * kPeriod), kPeriod, out);
      at += m;
    }
  }
}

void expect_same_structure(const StructuredFactorStream& got, const StructuredFactorStream& want) {
  const auto& a = got.structure();
  const auto& b = want.structure();
  EXPECT_EQ(a.ready, b.ready);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_TRUE(same_bits(a.centre, b.centre));
  EXPECT_EQ(a.order, b.order);
  EXPECT_TRUE(same_bits(a.b0, b.b0));
  EXPECT_EQ(a.instantaneous_allowed, b.instantaneous_allowed);
  EXPECT_EQ(a.problem, b.problem);
  ASSERT_EQ(got.stream() != nullptr, want.stream() != nullptr);
  if (got.stream()) {
    EXPECT_EQ(got.stream()->layout().factor_names(), want.stream()->layout().factor_names());
    EXPECT_EQ(got.stream()->counters().rejected_non_finite, want.stream()->counters().rejected_non_finite);
    EXPECT_EQ(got.stream()->samples_seen(), want.stream()->samples_seen());
  }
}

TEST(StructuredFactorStreamCheckpoint, ConditionLevelLearningCutBeforeAtAndAfterTheWindow) {
  const RowMajorMatrix y = series(300);
  StructuredFactorStream whole(condition_params(), learn_all(100));
  std::vector<FactorReport> want;
  feed_rows(whole, y, 0, 300, want);
  whole.finish(want);
  ASSERT_TRUE(whole.structure().problem.empty()) << whole.structure().problem;
  ASSERT_EQ(whole.structure().order.size(), 4u) << "the learned path must run";
  ASSERT_EQ(want.front().sample_index, kFirstSnapshot) << "reports carry the source's snapshot index";

  for (Eigen::Index cut : {0, 1, 50, 99, 100, 101, 120, 150, 200, 299, 300}) {
    SCOPED_TRACE("cut at vector " + std::to_string(cut));
    StructuredFactorStream first(condition_params(), learn_all(100));
    std::vector<FactorReport> got;
    feed_rows(first, y, 0, cut, got);
    StructuredFactorStream second(condition_params(), learn_all(100));
    restore_from(second, checkpoint_of(first));
    expect_same_structure(second, first);
    feed_rows(second, y, cut, 300, got);
    second.finish(got);
    expect_identical(got, want, "cut");
    expect_same_structure(second, whole);
  }
}

TEST(StructuredFactorStreamCheckpoint, StructureWindowThenNoiseWindow) {
  // Sample-level style: centre on the first 150 samples, then tune the noise on the next 200, fixed lag 8.
  FactorStreamParams p = condition_params();
  p.model.include_self_lags = false;
  p.noise.automatic = true;
  p.noise.calibration_samples = 200;
  p.publish_every = 10;
  p.fixed_lag = 8;
  StructureSetting centre_only;
  centre_only.calibration_samples = 150;
  centre_only.centre = true;
  const RowMajorMatrix y = series(500);
  StructuredFactorStream whole(p, centre_only);
  std::vector<FactorReport> want;
  feed_rows(whole, y, 0, 500, want);
  whole.finish(want);
  for (Eigen::Index cut : {75, 150, 151, 250, 350, 351, 420}) {
    SCOPED_TRACE("cut at sample " + std::to_string(cut));
    StructuredFactorStream first(p, centre_only), second(p, centre_only);
    std::vector<FactorReport> got;
    feed_rows(first, y, 0, cut, got);
    restore_from(second, checkpoint_of(first));
    feed_rows(second, y, cut, 500, got);
    second.finish(got);
    expect_identical(got, want, "cut");
    expect_same_structure(second, whole);
  }
}

TEST(StructuredFactorStreamCheckpoint, OtherSettingsAreRefused) {
  const RowMajorMatrix y = series(150);
  StructuredFactorStream first(condition_params(), learn_all(100));
  std::vector<FactorReport> ignored;
  feed_rows(first, y, 0, 150, ignored);
  const std::string bytes = checkpoint_of(first);
  auto message = [&](FactorStreamParams p, StructureSetting s) -> std::string {
    StructuredFactorStream other(p, s);
    try {
      restore_from(other, bytes);
    } catch (const estimation::StateError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(condition_params(), learn_all(120)),
            "checkpoint has structure calibration_samples 100, this structured factor stream has 120");
  StructureSetting no_order = learn_all(100);
  no_order.learn_order = false;
  EXPECT_EQ(message(condition_params(), no_order),
            "checkpoint has causal-order learning on, this structured factor stream has off");
  FactorStreamParams p = condition_params();
  p.fixed_lag = 3;
  EXPECT_EQ(message(p, learn_all(100)), "checkpoint has fixed lag 6, this structured factor stream has 3");
  StructuredFactorStream fresh(condition_params(), learn_all(100));
  for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 150) {
    EXPECT_THROW(restore_from(fresh, bytes.substr(0, n)), estimation::StateError) << "truncated to " << n;
  }
  EXPECT_EQ(fresh.stream(), nullptr) << "failed restores leave the fresh stream untouched";
}

}  // namespace

}  // namespace causal::pipeline
