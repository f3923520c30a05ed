// FactorStream with its automatic noise tuned on a TuningWorker (off the feeding thread): the reports must be,
// bit for bit, those of the stream that tunes on the feeding thread, whenever the worker's result arrives
// (held until the end, released in the middle of the input, waited for when the buffer reaches its bound), and a
// checkpoint taken while the worker tunes must continue, after a restore into a fresh stream with or without a
// worker, to the same reports. Once the result is in, the buffered window is replayed a share per feed (the
// samples fed meanwhile queue behind it), with the same reports, also across a checkpoint taken mid-replay.
#include "causal/pipeline/factor_stream.hpp"

#include "checkpoint_test_util.hpp"
#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

namespace causal::pipeline {
namespace {

using causal::test::checkpoint_of;
using causal::test::expect_identical;
using causal::test::restore_from;

constexpr std::int64_t kT0 = 1'650'000'000'000'000'000LL;
constexpr double kPeriod = 50'000.0;
constexpr Eigen::Index kRows = 1500;

// Tuned on `worker` when given, else on the feeding thread.
FactorStreamParams tuned_params(std::shared_ptr<TuningWorker> worker = nullptr) {
  FactorStreamParams p = causal::test::tuned_stream_params();
  p.noise.worker = std::move(worker);
  return p;
}

RowMajorMatrix data() {
  const estimation::SvarLayout layout(tuned_params().model);
  return causal::test::simulate_svar(layout, static_cast<int>(kRows), 23);
}

// Rows [from, to) in irregular blocks; row 0 starts with a discontinuity.
void feed_rows(FactorStream& s, const RowMajorMatrix& y, Eigen::Index from, Eigen::Index to,
               std::vector<FactorReport>& out) {
  Eigen::Index at = from;
  for (Eigen::Index b : causal::test::irregular_blocks(to - from)) {
    s.feed(y.middleRows(at, b), static_cast<std::uint64_t>(at), at == 0, kT0 + static_cast<std::int64_t>(at) * 50'000,
           kPeriod, out);
    at += b;
  }
}

std::vector<FactorReport> on_this_thread(const RowMajorMatrix& y) {
  FactorStream s(tuned_params());
  std::vector<FactorReport> out;
  feed_rows(s, y, 0, kRows, out);
  s.finish(out);
  return out;
}

TEST(FactorStreamWorker, HeldUntilFinishGivesTheSameReports) {
  const RowMajorMatrix y = data();
  const auto want = on_this_thread(y);
  ASSERT_GT(want.size(), 100u);

  auto worker = std::make_shared<TuningWorker>();
  worker->hold(true);  // the tuning cannot finish before finish(): every sample after the window is buffered
  FactorStream s(tuned_params(worker));
  std::vector<FactorReport> got;
  feed_rows(s, y, 0, kRows, got);
  EXPECT_TRUE(got.empty()) << "nothing can be reported before the noise is known";
  EXPECT_FALSE(s.calibrated());
  EXPECT_TRUE(s.tuning_in_background());
  EXPECT_EQ(worker->submitted(), 1u) << "one tuning per stream";
  worker->hold(false);
  s.finish(got);  // waits for the worker, replays all 1500 samples
  EXPECT_FALSE(s.tuning_in_background());
  expect_identical(got, want, "held until finish");
  EXPECT_EQ(s.samples_seen(), static_cast<std::uint64_t>(kRows));
}

TEST(FactorStreamWorker, ReleasedMidwayGivesTheSameReportsAtALaterFeed) {
  const RowMajorMatrix y = data();
  const auto want = on_this_thread(y);

  auto worker = std::make_shared<TuningWorker>();
  worker->hold(true);
  FactorStream s(tuned_params(worker));
  std::vector<FactorReport> got;
  feed_rows(s, y, 0, 800, got);
  ASSERT_TRUE(got.empty());
  worker->hold(false);
  while (s.tuning_in_background()) {  // the next feed takes the result once it is ready
    std::vector<FactorReport> none;
    s.feed(y.middleRows(800, 0), 800, false, kT0 + 800 * 50'000, kPeriod, none);
    got.insert(got.end(), none.begin(), none.end());
  }
  EXPECT_TRUE(s.calibrated());
  EXPECT_FALSE(got.empty()) << "the replay of the buffered samples began when the result arrived";
  feed_rows(s, y, 800, kRows, got);
  s.finish(got);
  expect_identical(got, want, "released midway");
}

TEST(FactorStreamWorker, ABufferAtItsBoundWaitsForTheTuningWithTheSameReports) {
  const RowMajorMatrix y = data();
  // calibration 100: the stream buffers at most 8 x 100 = 800 samples while the worker tunes.
  auto params = [](std::shared_ptr<TuningWorker> w) {
    FactorStreamParams p = tuned_params(std::move(w));
    p.noise.calibration_samples = 100;
    return p;
  };
  FactorStream sync(params(nullptr));
  std::vector<FactorReport> expected;
  feed_rows(sync, y, 0, kRows, expected);
  sync.finish(expected);

  auto worker = std::make_shared<TuningWorker>();
  worker->hold(true);
  FactorStream s(params(worker));
  std::vector<FactorReport> got;
  feed_rows(s, y, 0, 799, got);
  ASSERT_TRUE(s.tuning_in_background()) << "799 buffered samples: still below the bound";
  std::thread release([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    worker->hold(false);
  });
  feed_rows(s, y, 799, kRows, got);  // the 800th sample waits for the worker
  release.join();
  EXPECT_FALSE(s.tuning_in_background());
  EXPECT_TRUE(s.calibrated());
  s.finish(got);
  expect_identical(got, expected, "bounded buffer");
}

TEST(FactorStreamWorker, CheckpointWhileTuningContinuesToTheSameReports) {
  const RowMajorMatrix y = data();
  const auto want = on_this_thread(y);
  for (const bool restored_with_worker : {false, true}) {
    SCOPED_TRACE(restored_with_worker ? "restored with a worker" : "restored without a worker");
    auto worker = std::make_shared<TuningWorker>();
    worker->hold(true);
    FactorStream first(tuned_params(worker));
    std::vector<FactorReport> got;
    feed_rows(first, y, 0, 640, got);  // window full at 300, 340 more buffered
    ASSERT_TRUE(first.tuning_in_background());
    const std::string bytes = checkpoint_of(first);
    FactorStream second(tuned_params(restored_with_worker ? std::make_shared<TuningWorker>() : nullptr));
    restore_from(second, bytes);
    EXPECT_FALSE(second.calibrated());
    feed_rows(second, y, 640, kRows, got);
    second.finish(got);
    expect_identical(got, want, "checkpoint while tuning");
    worker->hold(false);  // the first stream's tuning finishes and is never used
  }
}

// Feeds empty blocks until the worker's result is taken (the feed that takes it starts the replay).
void take_result(FactorStream& s, Eigen::Index at, std::vector<FactorReport>& got) {
  while (s.tuning_in_background()) {
    s.feed(RowMajorMatrix(0, causal::test::tuned_stream_params().model.channels), static_cast<std::uint64_t>(at), false,
           kT0 + at * 50'000, kPeriod, got);
  }
}

TEST(FactorStreamWorker, TheWindowIsReplayedASharePerFeedWithTheSameReports) {
  const RowMajorMatrix y = data();
  const auto want = on_this_thread(y);
  auto worker = std::make_shared<TuningWorker>();
  worker->hold(true);
  FactorStream s(tuned_params(worker));
  std::vector<FactorReport> got;
  feed_rows(s, y, 0, 800, got);  // window full at 300, 500 more buffered
  ASSERT_EQ(s.samples_seen(), 0u);
  worker->hold(false);
  take_result(s, 800, got);
  const std::size_t share = 300 / NoiseSetting::kReplayShare;  // calibration_samples / kReplayShare = 75
  EXPECT_TRUE(s.calibrated());
  EXPECT_EQ(s.samples_seen(), share) << "the feed that takes the result replays one share, not the window";
  EXPECT_EQ(s.replay_pending(), 800 - share);
  s.feed(y.middleRows(800, 10), 800, false, kT0 + 800 * 50'000, kPeriod, got);
  EXPECT_EQ(s.samples_seen(), share + 10 + share) << "a feed replays what it brings plus one share";
  EXPECT_EQ(s.replay_pending(), 800 - 2 * share);
  feed_rows(s, y, 810, kRows, got);
  EXPECT_EQ(s.replay_pending(), 0u);
  s.finish(got);
  expect_identical(got, want, "replayed a share per feed");
}

TEST(FactorStreamWorker, CheckpointDuringTheReplayContinuesToTheSameReports) {
  const RowMajorMatrix y = data();
  const auto want = on_this_thread(y);
  for (const bool restored_with_worker : {false, true}) {
    SCOPED_TRACE(restored_with_worker ? "restored with a worker" : "restored without a worker");
    auto worker = std::make_shared<TuningWorker>();
    worker->hold(true);
    FactorStream first(tuned_params(worker));
    std::vector<FactorReport> got;
    feed_rows(first, y, 0, 700, got);
    worker->hold(false);
    take_result(first, 700, got);
    ASSERT_GT(first.replay_pending(), 0u);
    FactorStream second(tuned_params(restored_with_worker ? std::make_shared<TuningWorker>() : nullptr));
    restore_from(second, checkpoint_of(first));
    EXPECT_TRUE(second.calibrated());
    EXPECT_EQ(second.replay_pending(), first.replay_pending());
    feed_rows(second, y, 700, kRows, got);
    second.finish(got);
    expect_identical(got, want, "checkpoint during the replay");
  }
}

}  // namespace
}  // namespace causal::pipeline
