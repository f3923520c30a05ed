// causal::pipeline::ConditionStream: one condition vector per segment / window, against closed forms
// (RMS of a sine over whole periods), with the documented closing rules, drop counting and log transform.
#include "causal/pipeline/condition_stream.hpp"

#include "checkpoint_test_util.hpp"
#include "matrix_asserts.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace causal::pipeline {
namespace {

using causal::io::ConditionFeature;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr double kPi = 3.14159265358979323846;
constexpr std::int64_t kT0 = 1'600'000'000'000'000'000LL;

// Channel c: offset[c] + amp[c] sin(2 pi cycles[c] n / N + phase c). Over N samples covering whole periods
// (0 < cycles < N/2): mean sin = 0 and mean sin^2 = 1/2 exactly, so RMS = sqrt(offset^2 + amp^2 / 2).
RowMajor sines(int n, const std::vector<double>& amp, const std::vector<double>& offset,
               const std::vector<int>& cycles) {
  const int g = static_cast<int>(amp.size());
  RowMajor y(n, g);
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < g; ++c) {
      y(i, c) = offset[static_cast<std::size_t>(c)] +
                amp[static_cast<std::size_t>(c)] *
                    std::sin(2.0 * kPi * cycles[static_cast<std::size_t>(c)] * i / n + 0.3 * c);
    }
  }
  return y;
}

Eigen::VectorXd sine_rms(const std::vector<double>& amp, const std::vector<double>& offset) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(amp.size()));
  for (std::size_t c = 0; c < amp.size(); ++c) r[static_cast<Eigen::Index>(c)] = std::sqrt(offset[c] * offset[c] + amp[c] * amp[c] / 2.0);
  return r;
}

ConditionStreamParams params(std::size_t window, std::size_t min_samples, bool log_transform = true) {
  ConditionStreamParams p;
  p.feature = ConditionFeature::Rms;
  p.log_transform = log_transform;
  p.window_samples = window;
  p.min_samples = min_samples;
  return p;
}

// Feeds y in frames of `frame` rows; the first has discontinuity, the last end_of_segment (if asked). The
// source numbers the segment `snapshot` and its first sample `first_sample`.
void feed_segment(ConditionStream& s, const RowMajor& y, int frame, std::int64_t t0, bool end_of_segment,
                  std::vector<ConditionSample>& out, std::uint64_t snapshot = 0, std::uint64_t first_sample = 0,
                  std::int64_t period_ns = 50'000) {
  for (int at = 0; at < y.rows(); at += frame) {
    const int rows = std::min<int>(frame, static_cast<int>(y.rows()) - at);
    const bool last = at + rows == y.rows();
    s.feed(y.data() + static_cast<std::ptrdiff_t>(at) * y.cols(), static_cast<std::size_t>(rows),
           first_sample + static_cast<std::uint64_t>(at), snapshot, at == 0, end_of_segment && last,
           t0 + at * period_ns, static_cast<double>(period_ns), out);
  }
}

TEST(ConditionStream, RmsOfASegmentEqualsTheSineClosedForm) {
  const std::vector<double> amp{1.0, 0.25, 3.0}, offset{0.0, 0.5, -1.0};
  const RowMajor y = sines(4096, amp, offset, {7, 100, 1});
  ConditionStream s(params(0, 256), 3);
  std::vector<ConditionSample> out;
  feed_segment(s, y, 500, kT0, true, out);  // 500 does not divide 4096: a short last frame
  ASSERT_EQ(out.size(), 1u);
  const ConditionSample& c = out[0];
  EXPECT_EQ(c.snapshot_index, 0u);
  EXPECT_EQ(c.time_ns, kT0);
  EXPECT_EQ(c.samples, 4096u);
  EXPECT_TRUE(c.discontinuity);  // the first vector restarts the condition-level lags
  EXPECT_MATRIX_NEAR(c.values, sine_rms(amp, offset), 1e-12);
  EXPECT_MATRIX_NEAR(c.model_input, sine_rms(amp, offset).array().log().matrix(), 1e-12);
  EXPECT_EQ(s.dropped_windows(), 0u);
}

TEST(ConditionStream, SegmentsClosedAtEndOfSegment) {
  ConditionStream s(params(0, 100), 2);
  std::vector<ConditionSample> out;
  const std::vector<double> off{0.0, 0.0};
  for (int seg = 0; seg < 4; ++seg) {
    const std::vector<double> amp{1.0 + seg, 0.5};
    // The source numbers its snapshots 10, 12, 14, 16 (it skipped some): the vectors carry those numbers.
    const auto snapshot = static_cast<std::uint64_t>(10 + 2 * seg);
    feed_segment(s, sines(1000, amp, off, {5, 9}), 128, kT0 + seg * 600'000'000'000LL, true, out, snapshot,
                 snapshot * 1000);
    ASSERT_EQ(out.size(), static_cast<std::size_t>(seg + 1)) << "segment " << seg << " closed at its last frame";
    const ConditionSample& c = out.back();
    EXPECT_EQ(c.snapshot_index, snapshot);
    EXPECT_EQ(c.time_ns, kT0 + seg * 600'000'000'000LL);
    EXPECT_EQ(c.samples, 1000u);
    EXPECT_EQ(c.discontinuity, seg == 0) << "consecutive snapshots continue the condition-level series";
    EXPECT_MATRIX_NEAR(c.values, sine_rms(amp, off), 1e-12);
  }
}

TEST(ConditionStream, ANewDiscontinuityClosesTheOpenSegment) {
  // Segments whose last frame did not say end_of_segment: the next segment's first frame closes them.
  ConditionStream s(params(0, 100), 2);
  std::vector<ConditionSample> out;
  const std::vector<double> off{0.0, 0.0};
  const std::vector<double> a1{2.0, 1.0}, a2{0.5, 4.0};
  feed_segment(s, sines(800, a1, off, {3, 4}), 100, kT0, false, out);
  EXPECT_TRUE(out.empty()) << "still open";
  feed_segment(s, sines(1200, a2, off, {6, 2}), 100, kT0 + 1'000'000'000, false, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].samples, 800u);
  EXPECT_EQ(out[0].time_ns, kT0);
  EXPECT_MATRIX_NEAR(out[0].values, sine_rms(a1, off), 1e-12);
  // The second segment closes at the next discontinuity too (a zero-row frame only to mark it).
  const RowMajor none(0, 2);
  s.feed(none.data(), 0, 2000, 2, true, false, kT0 + 2'000'000'000, 50e3, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].samples, 1200u);
  EXPECT_EQ(out[1].time_ns, kT0 + 1'000'000'000);
  EXPECT_MATRIX_NEAR(out[1].values, sine_rms(a2, off), 1e-12);
  EXPECT_FALSE(out[1].discontinuity);
}

TEST(ConditionStream, WindowSamplesClosesWindowsOnAContinuousStream) {
  // A continuous sensor: no discontinuity after the first frame, never end_of_segment. Frames of 64 samples,
  // windows of 256: every window covers 4 frames and whole sine periods. The source had published 5
  // windows' worth of samples before: window w starts at sample (5 + w) * 256, so its index is 5 + w
  // (the frames' snapshot index, 7, is not used for windows closed by sample count).
  const std::vector<double> amp{1.5, 0.2}, off{0.1, 0.0};
  const int window = 256;
  const RowMajor y = sines(window * 5, amp, off, {5 * 4, 5 * 16});  // 4 and 16 cycles per window
  ConditionStream s(params(window, 100), 2);
  std::vector<ConditionSample> out;
  for (int at = 0; at < y.rows(); at += 64) {
    s.feed(y.data() + at * 2, 64, static_cast<std::uint64_t>(5 * window + at), 7, at == 0, false,
           kT0 + at * 50'000LL, 50e3, out);
  }
  ASSERT_EQ(out.size(), 5u);
  for (std::size_t w = 0; w < out.size(); ++w) {
    EXPECT_EQ(out[w].samples, static_cast<std::size_t>(window));
    EXPECT_EQ(out[w].time_ns, kT0 + static_cast<std::int64_t>(w) * window * 50'000LL);
    EXPECT_EQ(out[w].snapshot_index, 5 + w);
    EXPECT_EQ(out[w].discontinuity, w == 0);
    EXPECT_MATRIX_NEAR(out[w].values, sine_rms(amp, off), 1e-12);
  }
}

// The parameter says "close a window after this many samples"; a frame longer than the window must not make
// the window longer than window_samples (a 4096-sample frame with window_samples = 1024 is 4 windows).
TEST(ConditionStream, WindowSamplesHoldsWhenFramesAreLongerThanTheWindow) {
  const std::vector<double> amp{1.0, 2.0}, off{0.0, 0.0};
  const int window = 256;
  const RowMajor y = sines(window * 4, amp, off, {4 * 3, 4 * 7});
  ConditionStream s(params(window, 100), 2);
  std::vector<ConditionSample> out;
  s.feed(y.data(), static_cast<std::size_t>(y.rows()), 0, 0, true, false, kT0, 50e3, out);
  ASSERT_EQ(out.size(), 4u) << "one 1024-sample frame with window_samples = 256";
  for (const auto& c : out) {
    EXPECT_EQ(c.samples, static_cast<std::size_t>(window));
    EXPECT_MATRIX_NEAR(c.values, sine_rms(amp, off), 1e-12);
  }
}

TEST(ConditionStream, ShortSegmentsAreDroppedAndCounted) {
  ConditionStream s(params(0, 256), 2);
  std::vector<ConditionSample> out;
  const std::vector<double> amp{1.0, 1.0}, off{0.0, 0.0};
  feed_segment(s, sines(255, amp, off, {1, 2}), 100, kT0, true, out, 0);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(s.dropped_windows(), 1u);
  feed_segment(s, sines(256, amp, off, {1, 2}), 100, kT0 + 1'000'000, true, out, 1);  // exactly min_samples: kept
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].snapshot_index, 1u) << "the source's snapshot index: a dropped snapshot does not shift it";
  EXPECT_EQ(out[0].time_ns, kT0 + 1'000'000);
  feed_segment(s, sines(10, amp, off, {1, 2}), 100, kT0 + 2'000'000, false, out, 2);  // closed by the next one
  feed_segment(s, sines(300, amp, off, {1, 2}), 100, kT0 + 3'000'000, true, out, 3);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].snapshot_index, 3u);
  EXPECT_EQ(s.produced(), 2u);
  EXPECT_EQ(out[1].samples, 300u);
  EXPECT_EQ(s.dropped_windows(), 2u);
}

TEST(ConditionStream, NonFiniteRowsAreExcludedFromTheFeature) {
  const std::vector<double> amp{1.0, 0.5}, off{0.0, 0.0};
  RowMajor y = sines(512, amp, off, {4, 8});
  const RowMajor clean = y;
  y(100, 0) = std::numeric_limits<double>::quiet_NaN();
  y(200, 1) = std::numeric_limits<double>::infinity();
  ConditionStream s(params(0, 100), 2);
  std::vector<ConditionSample> out;
  feed_segment(s, y, 128, kT0, true, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].samples, 510u);
  // Expected: RMS over the 510 finite rows, computed here directly.
  Eigen::VectorXd expect = Eigen::VectorXd::Zero(2);
  for (int i = 0; i < 512; ++i) {
    if (i == 100 || i == 200) continue;
    expect += clean.row(i).transpose().cwiseAbs2();
  }
  expect = (expect / 510.0).cwiseSqrt();
  EXPECT_MATRIX_NEAR(out[0].values, expect, 1e-12);
}

TEST(ConditionStream, DropOpenWindowDiscardsCountsAndRestartsTheLags) {
  ConditionStream s(params(0, 100), 2);
  std::vector<ConditionSample> out;
  const std::vector<double> amp{1.0, 1.0}, off{0.0, 0.0};
  feed_segment(s, sines(400, amp, off, {1, 2}), 100, kT0, true, out);
  ASSERT_EQ(out.size(), 1u);
  // A gap between snapshots: nothing open, so nothing dropped, but whole snapshots may have been lost, so
  // the next vector still restarts the condition-level lags.
  s.drop_open_window();
  EXPECT_EQ(s.dropped_windows(), 0u);
  feed_segment(s, sines(400, amp, off, {1, 2}), 100, kT0 + 1'000'000, true, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[1].discontinuity);
  feed_segment(s, sines(400, amp, off, {1, 2}), 100, kT0 + 1'500'000, true, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_FALSE(out[2].discontinuity) << "only the first vector after a gap restarts";
  // Half a segment, then a gap.
  feed_segment(s, sines(200, amp, off, {1, 2}), 100, kT0 + 2'000'000, false, out);
  s.drop_open_window();
  EXPECT_EQ(s.dropped_windows(), 1u);
  const std::vector<double> a3{3.0, 0.1};
  feed_segment(s, sines(400, a3, off, {1, 2}), 100, kT0 + 3'000'000, true, out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_TRUE(out[3].discontinuity) << "the vector after a gap restarts the condition-level lags";
  EXPECT_EQ(out[3].samples, 400u) << "no sample of the dropped window may leak into the next";
  EXPECT_EQ(out[3].time_ns, kT0 + 3'000'000);
  EXPECT_MATRIX_NEAR(out[3].values, sine_rms(a3, off), 1e-12);
}

TEST(ConditionStream, OtherFeaturesUseTheBatchDefinition) {
  const std::vector<double> amp{1.0, 2.0}, off{0.0, 0.3};
  const RowMajor y = sines(1000, amp, off, {10, 3});
  for (ConditionFeature f : {ConditionFeature::MeanAbs, ConditionFeature::Kurtosis, ConditionFeature::Peak}) {
    ConditionStreamParams p = params(0, 100, false);
    p.feature = f;
    ConditionStream s(p, 2);
    std::vector<ConditionSample> out;
    feed_segment(s, y, 333, kT0, true, out);
    ASSERT_EQ(out.size(), 1u);
    const Eigen::VectorXd batch = causal::io::compute_condition_feature(Eigen::MatrixXd(y), f);
    EXPECT_MATRIX_NEAR(out[0].values, batch, 1e-10) << causal::io::to_string(f);
    EXPECT_MATRIX_NEAR(out[0].model_input, out[0].values, 0.0) << "no log transform requested";
  }
}

TEST(ConditionModelInput, LogTransformMapsNonPositiveToNaN) {
  Eigen::VectorXd v(5);
  v << 2.0, 0.0, -1.0, std::exp(1.0), 1.0;
  const Eigen::VectorXd l = condition_model_input(v, true);
  ASSERT_EQ(l.size(), 5);
  EXPECT_DOUBLE_EQ(l[0], std::log(2.0));
  EXPECT_TRUE(std::isnan(l[1]));
  EXPECT_TRUE(std::isnan(l[2]));
  EXPECT_NEAR(l[3], 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(l[4], 0.0);
  const Eigen::VectorXd same = condition_model_input(v, false);
  EXPECT_EQ(same, v);
}

TEST(ConditionModelInput, ConstantZeroChannelGivesNaNModelInput) {
  RowMajor y = RowMajor::Zero(300, 2);
  for (int i = 0; i < 300; ++i) y(i, 0) = std::sin(0.1 * i);
  ConditionStream s(params(0, 100, true), 2);
  std::vector<ConditionSample> out;
  feed_segment(s, y, 300, kT0, true, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].values[1], 0.0);
  EXPECT_TRUE(std::isnan(out[0].model_input[1]));
  EXPECT_TRUE(std::isfinite(out[0].model_input[0]));
}

TEST(ConditionStream, NeedsAtLeastOneChannel) {
  EXPECT_THROW(ConditionStream(params(0, 1), 0), std::invalid_argument);
}

// Checkpoint: cut between any two frames (inside a snapshot, right after its end, inside a count-closed
// window), save, restore into a fresh stream, feed the rest: the vectors and counters equal the
// uninterrupted run's bit for bit. Frames: 3 segments of 5 frames of 100 rows, the 2nd too short (dropped).
TEST(ConditionStream, CheckpointBetweenAnyTwoFramesGivesTheUninterruptedVectors) {
  const std::vector<double> amp{1.0, 0.5}, off{0.2, 0.0};
  const RowMajor y = sines(1500, amp, off, {7, 3});
  struct Frame {
    int at, rows;
    std::uint64_t snapshot;
    bool disc, end;
  };
  std::vector<Frame> frames;
  for (int seg = 0; seg < 3; ++seg) {
    const int rows = seg == 1 ? 40 : 100;  // segment 1: 200 rows < min_samples
    for (int f = 0; f < 5; ++f) frames.push_back({seg * 500 + f * 100, rows, std::uint64_t(20 + seg), f == 0, f == 4});
  }
  for (std::size_t window : {std::size_t{0}, std::size_t{256}}) {
    auto feed = [&](ConditionStream& s, std::size_t from, std::size_t to, std::vector<ConditionSample>& out) {
      for (std::size_t i = from; i < to; ++i) {
        const Frame& f = frames[i];
        s.feed(y.data() + f.at * 2, static_cast<std::size_t>(f.rows), 9000 + static_cast<std::uint64_t>(f.at),
               f.snapshot, f.disc, f.end, kT0 + f.at * 50'000LL, 50e3, out);
      }
    };
    ConditionStream whole(params(window, 250), 2);
    std::vector<ConditionSample> want;
    feed(whole, 0, frames.size(), want);
    ASSERT_GE(want.size(), 2u);
    for (std::size_t cut = 0; cut <= frames.size(); ++cut) {
      SCOPED_TRACE("window " + std::to_string(window) + ", cut before frame " + std::to_string(cut));
      ConditionStream first(params(window, 250), 2);
      std::vector<ConditionSample> got;
      feed(first, 0, cut, got);
      ConditionStream second(params(window, 250), 2);
      causal::test::restore_from(second, causal::test::checkpoint_of(first));
      feed(second, cut, frames.size(), got);
      causal::test::expect_identical(got, want);
      EXPECT_EQ(second.dropped_windows(), whole.dropped_windows());
      EXPECT_EQ(second.produced(), whole.produced());
    }
  }
  ConditionStream saved(params(0, 250), 2);
  const std::string bytes = causal::test::checkpoint_of(saved);
  ConditionStream other_window(params(256, 250), 2), other_channels(params(0, 250), 3);
  EXPECT_THROW(causal::test::restore_from(other_window, bytes), estimation::StateError);
  try {
    causal::test::restore_from(other_channels, bytes);
    ADD_FAILURE() << "3 channels accepted a 2-channel checkpoint";
  } catch (const estimation::StateError& e) {
    EXPECT_STREQ(e.what(), "checkpoint has 2 channels, this condition stream has 3");
  }
}

}  // namespace

}  // namespace causal::pipeline
