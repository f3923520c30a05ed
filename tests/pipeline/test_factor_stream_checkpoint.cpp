// FactorStream checkpoints: feeding a stream in two parts with save -> restore into a FRESH stream in
// between must give, bit for bit, the reports and counters of the uninterrupted run (the independent truth
// here), wherever the cut falls: inside the noise-calibration window, at its end, while filter reports wait
// for their fixed-lag twins. Restoring into a stream built with other parameters, or from a damaged or
// foreign checkpoint, must throw StateError. Reports carry the source's sample index.
#include "causal/pipeline/factor_stream.hpp"

#include "checkpoint_test_util.hpp"
#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace causal::pipeline {
namespace {

using causal::test::checkpoint_of;
using causal::test::expect_identical;
using causal::test::restore_from;
using causal::test::tuned_stream_params;

constexpr std::int64_t kT0 = 1'650'000'000'000'000'000LL;
constexpr double kPeriod = 50'000.0;
constexpr std::uint64_t kFirstIndex = 5'000;  // the source had published samples before

// 1500 samples with a rejected (NaN) sample and a discontinuity after the calibration window.
struct Data {
  RowMajorMatrix y;
  std::vector<bool> disc;
};

Data data() {
  const estimation::SvarLayout layout(tuned_stream_params().model);
  Data d{causal::test::simulate_svar(layout, 1500, 21), std::vector<bool>(1500, false)};
  d.y(700, 1) = std::numeric_limits<double>::quiet_NaN();
  d.disc[0] = true;
  d.disc[900] = true;
  return d;
}

// Rows [from, to) in irregular blocks, with the source index kFirstIndex + row.
void feed_rows(FactorStream& s, const Data& d, Eigen::Index from, Eigen::Index to, std::vector<FactorReport>& out,
               std::uint64_t first_index = kFirstIndex) {
  Eigen::Index at = from;
  for (Eigen::Index b : causal::test::irregular_blocks(to - from)) {
    const Eigen::Index end = at + b;
    while (at < end) {  // split a block at a discontinuity (the flag applies to a block's row 0)
      Eigen::Index m = 1;
      while (at + m < end && !d.disc[static_cast<std::size_t>(at + m)]) ++m;
      s.feed(d.y.middleRows(at, m), first_index + static_cast<std::uint64_t>(at), d.disc[static_cast<std::size_t>(at)],
             kT0 + static_cast<std::int64_t>(at) * 50'000, kPeriod, out);
      at += m;
    }
  }
}

// All 1500 rows through `s`, finished: the uninterrupted run.
std::vector<FactorReport> run_whole(FactorStream& s, const Data& d, std::uint64_t first_index = kFirstIndex) {
  std::vector<FactorReport> out;
  feed_rows(s, d, 0, 1500, out, first_index);
  s.finish(out);
  return out;
}

// The checkpoint of a fresh stream fed rows [0, rows).
std::string checkpoint_after(const Data& d, Eigen::Index rows) {
  FactorStream first(tuned_stream_params());
  std::vector<FactorReport> ignored;
  feed_rows(first, d, 0, rows, ignored);
  return checkpoint_of(first);
}

void expect_same_state(const FactorStream& got, const FactorStream& want) {
  EXPECT_EQ(got.samples_seen(), want.samples_seen());
  EXPECT_EQ(got.calibrated(), want.calibrated());
  EXPECT_EQ(got.counters().updated, want.counters().updated);
  EXPECT_EQ(got.counters().warm_up, want.counters().warm_up);
  EXPECT_EQ(got.counters().rejected_non_finite, want.counters().rejected_non_finite);
  ASSERT_EQ(got.noise().size(), want.noise().size());
  for (std::size_t k = 0; k < got.noise().size(); ++k) {
    EXPECT_TRUE(causal::test::same_bits(got.noise()[k].q, want.noise()[k].q));
    EXPECT_TRUE(causal::test::same_bits(got.noise()[k].r, want.noise()[k].r));
  }
  ASSERT_EQ(got.tuning().size(), want.tuning().size());
  for (std::size_t k = 0; k < got.tuning().size(); ++k) EXPECT_EQ(got.tuning()[k].message, want.tuning()[k].message);
}

TEST(FactorStreamCheckpoint, TwoHalvesWithRestoreEqualTheUninterruptedRunBitForBit) {
  const Data d = data();
  FactorStream whole(tuned_stream_params());
  const std::vector<FactorReport> want = run_whole(whole, d);
  ASSERT_GT(causal::test::of_kind(want, EstimateKind::FixedLag).size(), 0u);
  ASSERT_EQ(whole.counters().rejected_non_finite, 1u);

  // 0: nothing fed; 150: inside the calibration window; 299/300/301: around its end; 310: a filter report
  // waits for its fixed-lag twin; 700/701: around the rejected sample; 900: at the discontinuity; 1500: all.
  for (Eigen::Index cut : {0, 1, 150, 299, 300, 301, 310, 700, 701, 900, 1499, 1500}) {
    SCOPED_TRACE("cut at sample " + std::to_string(cut));
    FactorStream first(tuned_stream_params());
    std::vector<FactorReport> got;
    feed_rows(first, d, 0, cut, got);
    const std::string bytes = checkpoint_of(first);
    FactorStream second(tuned_stream_params());  // fresh, as after a restart
    restore_from(second, bytes);
    expect_same_state(second, first);
    feed_rows(second, d, cut, 1500, got);
    second.finish(got);
    expect_identical(got, want, "cut");
    expect_same_state(second, whole);
  }
}

TEST(FactorStreamCheckpoint, TwoRestartsInARow) {
  const Data d = data();
  FactorStream whole(tuned_stream_params());
  const std::vector<FactorReport> want = run_whole(whole, d);

  FactorStream a(tuned_stream_params());
  std::vector<FactorReport> got;
  feed_rows(a, d, 0, 150, got);
  FactorStream b(tuned_stream_params());
  restore_from(b, checkpoint_of(a));
  feed_rows(b, d, 150, 777, got);
  FactorStream c(tuned_stream_params());
  restore_from(c, checkpoint_of(b));
  feed_rows(c, d, 777, 1500, got);
  c.finish(got);
  expect_identical(got, want, "two restarts");
}

TEST(FactorStreamCheckpoint, ReportsCarryTheSourceIndex) {
  const Data d = data();
  FactorStream counted(tuned_stream_params()), sourced(tuned_stream_params());
  const std::vector<FactorReport> a = run_whole(counted, d, 0), b = run_whole(sourced, d, 7'000'000);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(b[i].sample_index, a[i].sample_index + 7'000'000) << "report " << i;
    EXPECT_TRUE(causal::test::same_bits(a[i].factors, b[i].factors)) << "the index does not change the estimate";
  }
  // Filter and fixed-lag twins refer to the same source sample.
  const auto f = causal::test::of_kind(b, EstimateKind::Filter);
  const auto s = causal::test::of_kind(b, EstimateKind::FixedLag);
  ASSERT_EQ(f.size(), s.size());
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_EQ(f[i].sample_index, s[i].sample_index);
}

TEST(FactorStreamCheckpoint, OtherParametersAreRefusedAndLeaveTheStreamUnchanged) {
  const Data d = data();
  const std::string bytes = checkpoint_after(d, 400);

  auto message = [&](FactorStreamParams p) -> std::string {
    FactorStream other(p);
    try {
      restore_from(other, bytes);
    } catch (const estimation::StateError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(tuned_stream_params(4)), "checkpoint has 3 channels, this factor stream has 4");
  FactorStreamParams p = tuned_stream_params();
  p.publish_every = 50;
  EXPECT_EQ(message(p), "checkpoint has publish_every 25, this factor stream has 50");
  p = tuned_stream_params();
  p.fixed_lag = 8;
  EXPECT_EQ(message(p), "checkpoint has fixed lag 16, this factor stream has 8");
  p = tuned_stream_params();
  p.model.include_self_lags = true;
  EXPECT_EQ(message(p), "checkpoint has self lags off, this factor stream has on");
  p = tuned_stream_params();
  p.model.instantaneous_allowed.assign(3, std::vector<bool>(3, true));
  p.model.instantaneous_allowed[0][1] = false;
  EXPECT_EQ(message(p).rfind("checkpoint has another causal graph for outcome 1", 0), 0u) << message(p);

  // A refused restore leaves the stream as it was: fed from the start it matches an untouched stream.
  p = tuned_stream_params();
  p.publish_every = 50;
  FactorStream refused(p), untouched(p);
  EXPECT_THROW(restore_from(refused, bytes), estimation::StateError);
  std::vector<FactorReport> a, b;
  feed_rows(refused, d, 0, 1500, a);
  feed_rows(untouched, d, 0, 1500, b);
  expect_identical(a, b, "after a refused restore");
}

TEST(FactorStreamCheckpoint, TruncatedOrForeignCheckpointsThrow) {
  const Data d = data();
  const std::string bytes = checkpoint_after(d, 310);
  for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 200) {
    FactorStream s(tuned_stream_params());
    EXPECT_THROW(restore_from(s, bytes.substr(0, n)), estimation::StateError) << "truncated to " << n << " bytes";
  }
  estimation::StateWriter other;
  other.begin("structured_factor_stream", 1);
  FactorStream s(tuned_stream_params());
  try {
    restore_from(s, other.bytes());
    ADD_FAILURE() << "a foreign section was accepted";
  } catch (const estimation::StateError& e) {
    EXPECT_STREQ(e.what(), "checkpoint: expected section 'factor_stream', found 'structured_factor_stream'");
  }
}

}  // namespace

}  // namespace causal::pipeline
