// causal::pipeline::AssetPipeline: the per-asset wiring of the sample-level factor stream, the condition
// stream and the condition-level factor stream. Checked against the parts run by hand on the same data.
#include "causal/pipeline/asset_pipeline.hpp"

#include "matrix_asserts.hpp"
#include "pipeline_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace causal::pipeline {
namespace {

constexpr std::int64_t kT0 = 1'650'000'000'000'000'000LL;
constexpr double kRate = 20'000.0;  // 50 us per sample
const estimation::NoiseParams kSampleNoise{2e-5, 0.05, 0.5};
const estimation::NoiseParams kConditionNoise{1e-4, 1e-2, 1.0};

AssetPipelineParams params(bool sample, bool condition) {
  AssetPipelineParams p;
  p.sample_level = sample;
  p.sample.model.lag_order = 1;
  p.sample.noise.automatic = false;
  p.sample.noise.fixed = kSampleNoise;
  p.sample.publish_every = 32;
  p.sample.fixed_lag = 0;
  p.condition_level = condition;
  p.condition.feature = causal::io::ConditionFeature::Rms;
  p.condition.log_transform = true;
  p.condition.window_samples = 0;
  p.condition.min_samples = 100;
  p.condition_model.model.lag_order = 1;
  p.condition_model.model.include_self_lags = true;
  p.condition_model.noise.automatic = false;
  p.condition_model.noise.fixed = kConditionNoise;
  p.condition_model.publish_every = 1;
  p.condition_model.fixed_lag = 0;
  return p;
}

estimation::ModelSpec sample_spec(int g) {
  estimation::ModelSpec s;
  s.channels = g;
  s.lag_order = 1;
  return s;
}

// n samples of g channels simulated from the sample-level model (sample_spec(g)).
RowMajorMatrix simulated_samples(int g, int n, std::uint64_t seed) {
  const estimation::SvarLayout layout(sample_spec(g));
  return causal::test::simulate_svar(layout, n, seed);
}

TEST(AssetPipeline, FirstFrameFixesTheChannelCountAndAChangeIsRefused) {
  AssetPipeline pipe(params(true, true));
  PipelineOutput out;
  const RowMajorMatrix three = RowMajorMatrix::Random(64, 3);
  FrameCheck c = pipe.feed_frame(three, 0, 0, true, false, false, kT0, kRate, out);
  EXPECT_TRUE(c.ok) << c.problem;
  EXPECT_EQ(pipe.channels(), 3);
  ASSERT_NE(pipe.sample_stream(), nullptr);
  const auto seen = pipe.sample_stream()->samples_seen();
  EXPECT_EQ(seen, 64u);
  out.clear();

  const RowMajorMatrix four = RowMajorMatrix::Random(64, 4);
  c = pipe.feed_frame(four, 64, 0, false, true, false, kT0 + 64 * 50'000, kRate, out);
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.problem.find("4"), std::string::npos) << c.problem;
  EXPECT_NE(c.problem.find("3"), std::string::npos) << c.problem;
  // Nothing of the refused frame was fed anywhere.
  EXPECT_EQ(pipe.sample_stream()->samples_seen(), seen);
  EXPECT_TRUE(out.sample_reports.empty());
  EXPECT_TRUE(out.conditions.empty()) << "end_of_segment of a refused frame must not close the window";
  EXPECT_EQ(pipe.channels(), 3);

  Eigen::VectorXd cond(5);
  cond.setOnes();
  c = pipe.feed_condition(cond, 0, false, kT0, out);
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.problem.find("5"), std::string::npos) << c.problem;
  EXPECT_TRUE(out.condition_reports.empty());
}

TEST(AssetPipeline, FewerThanTwoChannelsIsRefusedAndDoesNotFixTheCount) {
  AssetPipeline pipe(params(true, true));
  PipelineOutput out;
  const RowMajorMatrix one = RowMajorMatrix::Random(16, 1);
  const FrameCheck c = pipe.feed_frame(one, 0, 0, true, false, false, kT0, kRate, out);
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.problem.find("2 channels"), std::string::npos) << c.problem;
  EXPECT_EQ(pipe.channels(), 0);
  EXPECT_EQ(pipe.sample_stream(), nullptr);
  const RowMajorMatrix two = RowMajorMatrix::Random(16, 2);
  EXPECT_TRUE(pipe.feed_frame(two, 0, 0, true, false, false, kT0, kRate, out).ok);
  EXPECT_EQ(pipe.channels(), 2);
}

// Four snapshots of 4 frames each; the third frame of snapshot 2 arrives after lost frames (gap). The sample
// level must restart its lags there, the condition level must drop snapshot 2 and restart its lags after.
// Indices are the source's: samples numbered from 1,000,000 with the lost frames' samples skipped, snapshots
// 40, 43, 46, 49; reports and vectors must carry exactly those.
TEST(AssetPipeline, GapRestartsSampleLagsAndDropsTheOpenConditionWindow) {
  const int g = 3, frame = 128, frames_per_snap = 4, snaps = 4;
  const estimation::SvarLayout layout(sample_spec(g));
  const int n = frame * frames_per_snap * snaps;
  const RowMajorMatrix y = causal::test::simulate_svar(layout, n, 77);
  AssetPipeline pipe(params(true, true));
  PipelineOutput out;
  std::vector<bool> disc(static_cast<std::size_t>(n), false);
  std::vector<std::int64_t> frame_time;
  const std::int64_t snap_period = 600'000'000'000LL;  // 10 min between snapshots
  int gap_frame = 2 * frames_per_snap + 2;
  const std::uint64_t first_index = 1'000'000, lost = 3 * frame;
  auto source_index = [&](std::uint64_t row) { return first_index + row + (row >= std::uint64_t(gap_frame * frame) ? lost : 0); };
  auto snapshot_of = [](std::uint64_t snap) { return 40 + 3 * snap; };
  for (int f = 0; f < frames_per_snap * snaps; ++f) {
    const int snap = f / frames_per_snap, pos = f % frames_per_snap;
    const bool first = pos == 0, last = pos == frames_per_snap - 1, gap = f == gap_frame;
    const std::int64_t t = kT0 + snap * snap_period + pos * frame * 50'000LL;
    frame_time.push_back(t);
    if (first || gap) disc[static_cast<std::size_t>(f * frame)] = true;
    const FrameCheck c = pipe.feed_frame(y.middleRows(f * frame, frame), source_index(std::uint64_t(f * frame)),
                                         snapshot_of(std::uint64_t(snap)), first, last, gap, t, kRate, out);
    ASSERT_TRUE(c.ok) << c.problem;
  }
  pipe.finish(out);

  // Sample level: exactly the filter with a discontinuity at every snapshot start and at the gap frame.
  // (Row times in this test are per snapshot; the reference only needs the sample order.)
  const auto expected = causal::test::reference_reports(layout, {kSampleNoise}, y, disc, 32);
  ASSERT_EQ(out.sample_reports.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& r = out.sample_reports[i];
    EXPECT_EQ(r.sample_index, source_index(expected[i].index));
    EXPECT_MATRIX_NEAR(r.factors, expected[i].factors, 1e-12);
    EXPECT_EQ(r.innovation_count, expected[i].innovation_count);
    // time = first time of the frame holding the sample + offset / rate.
    const int f = static_cast<int>(expected[i].index) / frame;
    EXPECT_EQ(r.time_ns, frame_time[static_cast<std::size_t>(f)] + (static_cast<std::int64_t>(expected[i].index) % frame) * 50'000);
  }

  // Condition level: snapshots 0, 1 complete; snapshot 2 loses its open window at the gap, and its remaining
  // frames (gap frame + last) form a 256-sample window; snapshot 3 complete.
  EXPECT_EQ(pipe.dropped_condition_windows(), 1u);
  ASSERT_EQ(out.conditions.size(), 4u);
  const int rows_of[4][2] = {{0, 512}, {512, 512}, {gap_frame * frame, 256}, {1536, 512}};
  const bool disc_of[4] = {true, false, true, false};
  for (int i = 0; i < 4; ++i) {
    const ConditionSample& c = out.conditions[static_cast<std::size_t>(i)];
    SCOPED_TRACE("condition vector " + std::to_string(i));
    EXPECT_EQ(c.snapshot_index, snapshot_of(std::uint64_t(i)));
    EXPECT_EQ(c.samples, static_cast<std::size_t>(rows_of[i][1]));
    EXPECT_EQ(c.discontinuity, disc_of[i]);
    EXPECT_EQ(c.time_ns, frame_time[static_cast<std::size_t>(rows_of[i][0] / frame)]);
    const Eigen::MatrixXd seg = y.middleRows(rows_of[i][0], rows_of[i][1]);
    const Eigen::VectorXd rms = (seg.colwise().squaredNorm() / rows_of[i][1]).cwiseSqrt().transpose();
    EXPECT_MATRIX_NEAR(c.values, rms, 1e-12);
  }

  // Condition-level factors: the filter on log(values) with the vectors' restart flags, one report per vector.
  RowMajorMatrix z(4, g);
  std::vector<bool> zdisc;
  for (int i = 0; i < 4; ++i) {
    z.row(i) = out.conditions[static_cast<std::size_t>(i)].values.array().log().matrix().transpose();
    zdisc.push_back(disc_of[i]);
  }
  estimation::ModelSpec cs = sample_spec(g);
  cs.include_self_lags = true;
  const estimation::SvarLayout clayout(cs);
  const auto cexp = causal::test::reference_reports(clayout, {kConditionNoise}, z, zdisc, 1);
  ASSERT_EQ(out.condition_reports.size(), cexp.size());
  for (std::size_t i = 0; i < cexp.size(); ++i) {
    const auto& r = out.condition_reports[i];
    EXPECT_EQ(r.sample_index, snapshot_of(cexp[i].index));
    EXPECT_EQ(r.outcome, cexp[i].outcome);
    EXPECT_EQ(r.time_ns, out.conditions[cexp[i].index].time_ns);
    EXPECT_MATRIX_NEAR(r.factors, cexp[i].factors, 1e-12);
    EXPECT_EQ(r.innovation_count, cexp[i].innovation_count);
  }
}

TEST(AssetPipeline, FeedConditionRunsTheConditionModelOnLogValues) {
  const int g = 4, n = 60;
  AssetPipelineParams p = params(false, true);
  p.condition_model.fixed_lag = 3;
  AssetPipeline pipe(p);
  PipelineOutput out;
  // Positive condition values following a log-linear SVAR (simulated in log space).
  estimation::ModelSpec cs = sample_spec(g);
  cs.include_self_lags = true;
  const estimation::SvarLayout clayout(cs);
  RowMajorMatrix z = causal::test::simulate_svar(clayout, n, 91, 1e-4, 1e-2);
  z(30, 2) = std::numeric_limits<double>::quiet_NaN();  // becomes a rejected sample
  std::vector<bool> zdisc(static_cast<std::size_t>(n), false);
  zdisc[0] = true;
  zdisc[40] = true;  // a restart announced by the condition vector
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd values = z.row(i).transpose().array().exp();
    if (i == 30) values[2] = -1.0;  // non-positive: log gives NaN, the filter rejects and counts it
    // Snapshot indices from the source, with holes (snapshots the source skipped): reports must carry them.
    const FrameCheck c = pipe.feed_condition(values, 500 + 2 * std::uint64_t(i), zdisc[static_cast<std::size_t>(i)],
                                             kT0 + i * 1000LL, out);
    ASSERT_TRUE(c.ok) << c.problem;
  }
  pipe.finish(out);
  EXPECT_EQ(pipe.sample_stream(), nullptr);
  ASSERT_NE(pipe.condition_stream(), nullptr);
  EXPECT_TRUE(out.sample_reports.empty());
  EXPECT_TRUE(out.conditions.empty()) << "ready-made vectors are not republished";

  const auto filt = causal::test::of_kind(out.condition_reports, EstimateKind::Filter);
  const auto smooth = causal::test::of_kind(out.condition_reports, EstimateKind::FixedLag);
  const auto expected = causal::test::reference_reports(clayout, {kConditionNoise}, z, zdisc, 1);
  ASSERT_EQ(filt.size(), static_cast<std::size_t>(n * g));
  ASSERT_EQ(filt.size(), expected.size());
  for (std::size_t i = 0; i < filt.size(); ++i) {
    EXPECT_EQ(filt[i].sample_index, 500 + 2 * expected[i].index);
    EXPECT_EQ(filt[i].time_ns, kT0 + static_cast<std::int64_t>(expected[i].index) * 1000);
    EXPECT_MATRIX_NEAR(filt[i].factors, expected[i].factors, 1e-10);  // log(exp(z)) vs z: rounding only
    EXPECT_EQ(filt[i].rejected, expected[i].rejected);
  }
  EXPECT_EQ(filt.back().rejected, 1u);
  EXPECT_EQ(smooth.size(), filt.size()) << "finish() flushes the fixed-lag smoother";
}

TEST(AssetPipeline, FeedConditionRefusedWhenTheConditionLevelIsDisabled) {
  AssetPipeline pipe(params(true, false));
  PipelineOutput out;
  Eigen::VectorXd v = Eigen::VectorXd::Ones(3);
  const FrameCheck c = pipe.feed_condition(v, 0, true, kT0, out);
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.problem.find("disabled"), std::string::npos) << c.problem;
  EXPECT_TRUE(out.condition_reports.empty());
}

TEST(AssetPipeline, SampleLevelOnlyProducesNoConditions) {
  const int g = 2;
  const RowMajorMatrix y = simulated_samples(g, 256, 5);
  AssetPipeline pipe(params(true, false));
  PipelineOutput out;
  ASSERT_TRUE(pipe.feed_frame(y, 0, 0, true, true, false, kT0, kRate, out).ok);
  pipe.finish(out);
  EXPECT_EQ(out.sample_reports.size(), 256u / 32u * g);
  EXPECT_TRUE(out.conditions.empty());
  EXPECT_TRUE(out.condition_reports.empty());
  EXPECT_EQ(pipe.condition_stream(), nullptr);
  EXPECT_EQ(pipe.dropped_condition_windows(), 0u);
}

TEST(AssetPipeline, SampleTimesUseTheSampleRate) {
  const int g = 3;
  const RowMajorMatrix y = simulated_samples(g, 512, 6);
  AssetPipeline pipe(params(true, false));
  PipelineOutput out;
  const double rate = 25'600.0;  // 39062.5 ns per sample
  ASSERT_TRUE(pipe.feed_frame(y, 0, 0, true, false, false, kT0, rate, out).ok);
  ASSERT_EQ(out.sample_reports.size(), 512u / 32u * g);
  for (const auto& r : out.sample_reports) {
    EXPECT_EQ(r.time_ns, kT0 + std::llround(static_cast<double>(r.sample_index) * 1e9 / rate));
  }
}

}  // namespace

// Any channel count: the configured structure window (100 snapshots) is kept whatever the width, so healthy is
// learned on the same stretch of the run; where 100 cannot identify one dense VAR-LiNGAM order over G channels
// (10 x G x (M + 1) > 100) the order is learned per contiguous block of at most 100 / 20 = 5 channels, with no
// instantaneous link between blocks. Every vector of the window is replayed and estimated.
TEST(AssetPipeline, CalibrationWindowDoesNotGrowWithTheChannelCount) {
  AssetPipelineParams p = params(false, true);
  p.condition_structure.calibration_samples = 100;
  p.condition_structure.centre = true;
  p.condition_structure.learn_order = true;
  const std::map<int, std::vector<int>> block_sizes = {{2, {2}}, {4, {4}}, {5, {5}}, {8, {4, 4}},
                                                      {16, {4, 4, 4, 4}}, {20, {5, 5, 5, 5}}, {21, {5, 4, 4, 4, 4}}};
  for (const auto& [g, sizes] : block_sizes) {
    AssetPipeline pipe(p);
    PipelineOutput out;
    const std::size_t window = 100;
    std::uint64_t snapshot = 0;
    Eigen::VectorXd v(g);
    for (; snapshot < window; ++snapshot) {
      // Non-Gaussian (uniform-like) innovations so that every block's order can be learned.
      for (int c = 0; c < g; ++c) v[c] = std::exp(0.01 * std::sin(0.7 * static_cast<double>(snapshot * (c + 2)) + c));
      const FrameCheck check = pipe.feed_condition(v, snapshot, snapshot == 0, kT0 + static_cast<std::int64_t>(snapshot), out);
      ASSERT_TRUE(check.ok) << g << " channels: " << check.problem;
      ASSERT_EQ(pipe.condition_stream() != nullptr, snapshot + 1 == window) << g << " channels, snapshot " << snapshot;
    }
    const LearnedStructure& learned = *pipe.condition_structure();
    EXPECT_EQ(learned.samples, window) << g << " channels";
    EXPECT_TRUE(pipe.calibration_adjustments().empty()) << g << " channels";
    std::vector<int> got;
    int next = 0;
    for (const auto& b : learned.blocks) {
      got.push_back(static_cast<int>(b.size()));
      for (const int c : b) EXPECT_EQ(c, next++) << g << " channels: blocks are contiguous in channel order";
    }
    EXPECT_EQ(got, sizes) << g << " channels";
    // No instantaneous link between two blocks.
    ASSERT_EQ(learned.instantaneous_allowed.size(), static_cast<std::size_t>(g)) << learned.problem;
    std::vector<int> block_of(static_cast<std::size_t>(g));
    for (std::size_t b = 0; b < learned.blocks.size(); ++b)
      for (const int c : learned.blocks[b]) block_of[static_cast<std::size_t>(c)] = static_cast<int>(b);
    for (int k = 0; k < g; ++k)
      for (int j = 0; j < g; ++j)
        if (block_of[static_cast<std::size_t>(k)] != block_of[static_cast<std::size_t>(j)])
          EXPECT_FALSE(learned.instantaneous_allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)]) << g << ": " << j << "->" << k;
    EXPECT_EQ(causal::test::of_kind(out.condition_reports, EstimateKind::Filter).size(), window * static_cast<std::size_t>(g))
        << "the window is replayed: every vector is estimated";
  }
}

// Below what one block of two channels needs (10 x 2 x (M + 1) = 40 at lag 1), the window is raised and listed.
TEST(AssetPipeline, StructureWindowIsRaisedOnlyBelowOneBlock) {
  AssetPipelineParams p = params(false, true);
  p.condition_structure.calibration_samples = 30;
  p.condition_structure.centre = true;
  p.condition_structure.learn_order = true;
  AssetPipeline pipe(p);
  PipelineOutput out;
  ASSERT_TRUE(pipe.feed_condition(Eigen::VectorXd::Constant(8, 0.05), 0, true, kT0, out).ok);
  ASSERT_EQ(pipe.calibration_adjustments().size(), 1u);
  EXPECT_EQ(pipe.calibration_adjustments()[0].window, "condition-level structure");
  EXPECT_EQ(pipe.calibration_adjustments()[0].configured, 30u);
  EXPECT_EQ(pipe.calibration_adjustments()[0].used, 40u);
}

}  // namespace causal::pipeline
