// AssetPipeline checkpoints and source indices: an IMS-like asset group (G = 4, 4 frames per snapshot, both
// levels with the shipped kinds of settings: automatic noise + fixed lag at sample level, centre + VAR-LiNGAM
// at condition level) fed with save -> restore into a FRESH pipeline at a cut must give, bit for bit, the
// sample reports, condition vectors, condition reports and counters of the uninterrupted run (the truth).
// Cuts: inside the sample-level noise calibration, inside a snapshot, right after an end of segment, before
// and after the condition-level calibration window; also ready-made condition vectors (feed_condition),
// dedupe of re-sent input after a restart, and refused (other shape, truncated, foreign) checkpoints.
#include "causal/pipeline/asset_pipeline.hpp"

#include "checkpoint_test_util.hpp"
#include "pipeline_test_util.hpp"
#include "../support/ims_condition_model.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

#include <unistd.h>

namespace causal::pipeline {
namespace {

using causal::test::checkpoint_of;
using causal::test::expect_identical;
using causal::test::restore_from;

constexpr int kG = 4, kFrame = 128, kFramesPerSnapshot = 4, kSnapshots = 130;
constexpr int kSnapshotRows = kFrame * kFramesPerSnapshot;
constexpr std::int64_t kT0 = 1'076'581'959'000'000'000LL;  // 2004-02-12 10:32:39 UTC
constexpr std::int64_t kSnapshotPeriod = 600'000'000'000LL;
constexpr double kRate = 20'000.0;
constexpr std::uint64_t kFirstSample = 10'000'000, kFirstSnapshot = 1'000;

AssetPipelineParams params(bool sample_level = true) {
  AssetPipelineParams p;
  p.sample_level = sample_level;
  p.sample.model.lag_order = 1;
  p.sample.noise.automatic = true;
  p.sample.noise.fixed = estimation::NoiseParams{1e-6, 1e-2, 1.0};
  p.sample.noise.calibration_samples = 2048;  // the first 4 snapshots
  p.sample.publish_every = 128;
  p.sample.fixed_lag = 16;
  causal::test::set_ims_condition_model(p);
  p.condition.log_transform = true;
  p.condition.window_samples = 0;
  p.condition.min_samples = 256;
  return p;
}

struct Frame {
  Eigen::Index row;
  std::uint64_t snapshot;
  bool discontinuity, end_of_segment, gap;
  std::int64_t time_ns;
};

// Snapshot levels follow a non-Gaussian structural VAR (so VAR-LiNGAM can order them); the samples inside
// are a sample-level SVAR scaled per channel by the snapshot's level. Frame 1 of snapshot 30 is lost on the
// way (not fed; the next frame says gap), and one sample is NaN (rejected at sample level).
struct Recording {
  RowMajorMatrix y;
  std::vector<Frame> frames;
};

Recording make_recording() {
  estimation::ModelSpec spec;
  spec.channels = kG;
  spec.lag_order = 1;
  Recording run{causal::test::simulate_svar(estimation::SvarLayout(spec), kSnapshots * kSnapshotRows, 3, 1e-10), {}};
  const Eigen::MatrixXd level = causal::test::simulate_lingam(kSnapshots, 5, 0.3, 0.0);
  for (int s = 0; s < kSnapshots; ++s) {
    for (int j = 0; j < kG; ++j) run.y.block(s * kSnapshotRows, j, kSnapshotRows, 1) *= std::exp(level(s, j));
  }
  run.y(70 * kSnapshotRows + 5, 3) = std::numeric_limits<double>::quiet_NaN();
  for (int s = 0; s < kSnapshots; ++s) {
    for (int f = 0; f < kFramesPerSnapshot; ++f) {
      if (s == 30 && f == 1) continue;  // lost
      run.frames.push_back({Eigen::Index(s) * kSnapshotRows + f * kFrame, kFirstSnapshot + std::uint64_t(s), f == 0,
                            f == kFramesPerSnapshot - 1, s == 30 && f == 2,
                            kT0 + s * kSnapshotPeriod + f * kFrame * 50'000LL});
    }
  }
  return run;
}

std::uint64_t first_sample(const Frame& f) { return kFirstSample + static_cast<std::uint64_t>(f.row); }

void feed(AssetPipeline& p, const Recording& run, std::size_t from, std::size_t to, PipelineOutput& out) {
  for (std::size_t i = from; i < to; ++i) {
    const Frame& f = run.frames[i];
    const auto check = p.feed_frame(run.y.middleRows(f.row, kFrame), first_sample(f), f.snapshot, f.discontinuity,
                                    f.end_of_segment, f.gap, f.time_ns, kRate, out);
    ASSERT_TRUE(check.ok) << check.problem;
  }
}

void append(PipelineOutput& to, const PipelineOutput& from) {
  causal::test::append(to.sample_reports, from.sample_reports);
  causal::test::append(to.condition_reports, from.condition_reports);
  causal::test::append(to.conditions, from.conditions);
}

void expect_identical_output(const PipelineOutput& got, const PipelineOutput& want) {
  expect_identical(got.sample_reports, want.sample_reports, "sample level");
  expect_identical(got.condition_reports, want.condition_reports, "condition level");
  expect_identical(got.conditions, want.conditions);
}

void expect_same_counters(const AssetPipeline& got, const AssetPipeline& want) {
  EXPECT_EQ(got.channels(), want.channels());
  EXPECT_EQ(got.dropped_condition_windows(), want.dropped_condition_windows());
  EXPECT_EQ(got.last_source_index().sample, want.last_source_index().sample);
  EXPECT_EQ(got.last_source_index().snapshot, want.last_source_index().snapshot);
  for (auto level : {&AssetPipeline::sample_stream, &AssetPipeline::condition_stream}) {
    const auto* a = (got.*level)();
    const auto* b = (want.*level)();
    ASSERT_EQ(a != nullptr, b != nullptr);
    if (!a) continue;
    EXPECT_EQ(a->samples_seen(), b->samples_seen());
    EXPECT_EQ(a->counters().updated, b->counters().updated);
    EXPECT_EQ(a->counters().warm_up, b->counters().warm_up);
    EXPECT_EQ(a->counters().rejected_non_finite, b->counters().rejected_non_finite);
  }
}

class AssetPipelineCheckpoint : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    run_ = new Recording(make_recording());
    whole_ = new AssetPipeline(params());
    want_ = new PipelineOutput;
    feed(*whole_, *run_, 0, run_->frames.size(), *want_);
    whole_->finish(*want_);
  }
  static void TearDownTestSuite() {
    delete run_;
    delete whole_;
    delete want_;
  }
  static Recording* run_;
  static AssetPipeline* whole_;
  static PipelineOutput* want_;
};
Recording* AssetPipelineCheckpoint::run_ = nullptr;
AssetPipeline* AssetPipelineCheckpoint::whole_ = nullptr;
PipelineOutput* AssetPipelineCheckpoint::want_ = nullptr;

TEST_F(AssetPipelineCheckpoint, TheUninterruptedRunCarriesTheSourceIndices) {
  ASSERT_EQ(whole_->condition_structure()->order.size(), std::size_t(kG)) << whole_->condition_structure()->problem;
  ASSERT_EQ(whole_->sample_stream()->counters().rejected_non_finite, 1u);
  // Snapshot 30 lost a frame: its open window is dropped; every other snapshot gives one vector with its
  // source snapshot index, and condition reports carry it.
  EXPECT_EQ(whole_->dropped_condition_windows(), 1u);
  ASSERT_EQ(want_->conditions.size(), std::size_t(kSnapshots));  // 30: frames 2, 3 still make 256 samples
  for (std::size_t i = 0; i < want_->conditions.size(); ++i) EXPECT_EQ(want_->conditions[i].snapshot_index, kFirstSnapshot + i);
  for (const auto& r : want_->condition_reports) {
    EXPECT_GE(r.sample_index, kFirstSnapshot);
    EXPECT_LT(r.sample_index, kFirstSnapshot + kSnapshots);
  }
  // Sample reports carry kFirstSample + row; the lost frame's samples are never reported.
  for (const auto& r : want_->sample_reports) {
    const auto row = static_cast<Eigen::Index>(r.sample_index - kFirstSample);
    EXPECT_FALSE(row >= 30 * kSnapshotRows + kFrame && row < 30 * kSnapshotRows + 2 * kFrame) << r.sample_index;
  }
  EXPECT_EQ(whole_->last_source_index().sample, kFirstSample + std::uint64_t(kSnapshots) * kSnapshotRows - 1);
  EXPECT_EQ(whole_->last_source_index().snapshot, kFirstSnapshot + kSnapshots - 1);
}

TEST_F(AssetPipelineCheckpoint, SaveRestoreIntoAFreshPipelineEqualsTheUninterruptedRun) {
  const std::size_t per = kFramesPerSnapshot;
  // 0: nothing fed; 5: inside the sample-level calibration (2048 samples) and inside snapshot 1;
  // 50 * 4 + 2: inside a snapshot, before the condition window is full; 60 * 4 - 1: right after the end of
  // segment 59 (the lost frame shifts the list by one); 100 * 4 - 1: right after snapshot 99, the last of the
  // condition window; 120 * 4 + 1: after it; the end: only finish() remains.
  for (std::size_t cut : {std::size_t{0}, std::size_t{5}, 50 * per + 2, 60 * per - 1, 100 * per - 1, 120 * per + 1,
                          run_->frames.size()}) {
    SCOPED_TRACE("cut before frame " + std::to_string(cut));
    AssetPipeline first(params());
    PipelineOutput got, rest;
    feed(first, *run_, 0, cut, got);
    AssetPipeline second(params());  // fresh, as after kill -9 and a restart
    restore_from(second, checkpoint_of(first));
    expect_same_counters(second, first);
    feed(second, *run_, cut, run_->frames.size(), rest);
    second.finish(rest);
    append(got, rest);
    expect_identical_output(got, *want_);
    expect_same_counters(second, *whole_);
  }
}

TEST_F(AssetPipelineCheckpoint, ThroughAFileWithResentInputSkipped) {
  // The service's view: checkpoint to a file, restart, the source re-sends what it had in flight; the
  // pipeline's last source index tells which frames were fed before.
  const std::size_t cut = 77 * kFramesPerSnapshot + 1;
  const auto dir = std::filesystem::temp_directory_path() / ("causal_pipeline_ckpt_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "asset.ckpt").string();
  AssetPipeline first(params());
  PipelineOutput got, rest;
  feed(first, *run_, 0, cut, got);
  estimation::save_state_file(path, checkpoint_of(first));

  AssetPipeline second(params());
  const auto payload = estimation::load_state_file(path);
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(payload.has_value());
  restore_from(second, *payload);
  std::size_t skipped = 0;
  for (std::size_t i = cut - 3; i < run_->frames.size(); ++i) {  // 3 frames re-sent
    const Frame& f = run_->frames[i];
    if (second.already_fed_frame(first_sample(f), kFrame)) {
      ++skipped;
      continue;
    }
    feed(second, *run_, i, i + 1, rest);
  }
  EXPECT_EQ(skipped, 3u);
  second.finish(rest);
  append(got, rest);
  expect_identical_output(got, *want_);
}

TEST(AssetPipelineCheckpointConditions, ReadyMadeConditionVectors) {
  const int n = 200;
  const Eigen::MatrixXd z = causal::test::simulate_lingam(n, 9, 0.3, -2.5);
  auto feed_vectors = [&](AssetPipeline& p, int from, int to, PipelineOutput& out) {
    for (int i = from; i < to; ++i) {
      if (p.already_fed_condition(500 + 2 * std::uint64_t(i))) continue;
      const Eigen::VectorXd values = z.row(i).transpose().array().exp();
      ASSERT_TRUE(p.feed_condition(values, 500 + 2 * std::uint64_t(i), i == 0 || i == 150, kT0 + i * kSnapshotPeriod, out).ok);
    }
  };
  AssetPipeline whole(params(false));
  PipelineOutput want;
  feed_vectors(whole, 0, n, want);
  whole.finish(want);
  ASSERT_EQ(whole.condition_structure()->order.size(), std::size_t(kG)) << whole.condition_structure()->problem;
  EXPECT_EQ(want.condition_reports.front().sample_index, 500u);
  EXPECT_EQ(want.condition_reports.back().sample_index, 500u + 2 * (n - 1));
  for (int cut : {0, 60, 99, 100, 101, 150, 199}) {
    SCOPED_TRACE("cut before vector " + std::to_string(cut));
    AssetPipeline first(params(false)), second(params(false));
    PipelineOutput got, rest;
    feed_vectors(first, 0, cut, got);
    restore_from(second, checkpoint_of(first));
    feed_vectors(second, cut > 2 ? cut - 2 : 0, n, rest);  // two vectors re-sent: skipped
    second.finish(rest);
    append(got, rest);
    expect_identical_output(got, want);
    EXPECT_EQ(second.last_source_index().snapshot, 500u + 2 * (n - 1));
  }
}

TEST_F(AssetPipelineCheckpoint, AnotherShapeOrADamagedCheckpointIsRefused) {
  AssetPipeline four(params());
  PipelineOutput out;
  feed(four, *run_, 0, 9, out);
  const std::string bytes = checkpoint_of(four);

  AssetPipelineParams p8 = params();
  p8.condition_structure.calibration_samples = 160;  // VAR-LiNGAM needs 10 x G x (M + 1) vectors
  AssetPipeline eight(p8);
  ASSERT_TRUE(eight.feed_frame(RowMajorMatrix::Random(kFrame, 8), 0, 0, true, false, false, kT0, kRate, out).ok);
  try {
    restore_from(eight, bytes);
    ADD_FAILURE() << "an 8-channel asset group took a 4-channel checkpoint";
  } catch (const estimation::StateError& e) {
    EXPECT_STREQ(e.what(), "checkpoint has 4 channels, this asset group has 8");
  }
  EXPECT_EQ(eight.channels(), 8) << "a refused restore changes nothing";

  AssetPipeline named(params());
  named.set_channel_names({"b1", "b2", "b3", "b4", "b5", "b6", "b7", "b8"});
  EXPECT_THROW(restore_from(named, bytes), estimation::StateError);
  EXPECT_EQ(named.channels(), 0);

  AssetPipelineParams other = params();
  other.sample.publish_every = 256;
  AssetPipeline differently_configured(other);
  EXPECT_THROW(restore_from(differently_configured, bytes), estimation::StateError);
  EXPECT_EQ(differently_configured.channels(), 0) << "nothing built when the streams refuse";

  for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 300) {
    AssetPipeline fresh(params());
    EXPECT_THROW(restore_from(fresh, bytes.substr(0, n)), estimation::StateError) << "truncated to " << n;
    EXPECT_EQ(fresh.channels(), 0);
  }
  estimation::StateWriter foreign;
  foreign.begin("alarm_engine", 1);
  AssetPipeline fresh(params());
  EXPECT_THROW(restore_from(fresh, foreign.bytes()), estimation::StateError);
}

}  // namespace

}  // namespace causal::pipeline
