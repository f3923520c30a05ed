// causal-estimator's work per raw frame without DDS, stage by stage, in the same binary (and the same run) as the
// kernel BM_SampleLevelFactorStream: what AssetPipeline::feed_frame costs beside the filter and fixed-lag smoother,
// and where. The frames are those of deploy/bench_scale.sh's throughput runs: one asset group of 4 channels,
// 1024-sample frames from a continuous sensor (no end of segment, so no condition vector is closed), a stable
// SVAR(1) with uniform noise like sensor-sim's; the parameters are the shipped deploy/config/estimator.yaml
// (input screen, automatic sample-level noise on 4096 samples, fixed lag 16, condition features). Every stage is
// measured in its steady state (after the calibration window), per 1024-sample frame:
//   BM_FramePath/stage:0  whole      AssetPipeline::feed_frame (what the estimator's processing thread calls)
//   BM_FramePath/stage:1  copy       the frame copied into the pipeline's own buffer (the screen works in place)
//   BM_FramePath/stage:2  screen     the copy and InputScreen::screen on it (bad values, stuck and scale checks)
//   BM_FramePath/stage:3  sample     the sample-level StructuredFactorStream (filter, fixed-lag smoother, reports)
//   BM_FramePath/stage:4  condition  ConditionStream::feed (the condition features' running moments)
// and BM_FramePathStartup: one group's start-up (the first 4096 samples buffered, its noise tuned, the window
// replayed), which deploy/bench_scale.sh's cpu_per_frame_us spreads over its 500 frames per group.
// Run e.g. with repetitions interleaved, so a shared machine's changing speed hits every stage alike:
//   build/tests/bench/causal_bench_pipeline --benchmark_filter='BM_SampleLevelFactorStream/L:16$|BM_FramePath'
//       --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
// (docs/scale-and-benchmarks.md, "Per-frame work beside the kernel").
#include <benchmark/benchmark.h>

#include "causal/pipeline/asset_pipeline.hpp"
#include "causal/pipeline/condition_stream.hpp"
#include "causal/pipeline/estimator_params.hpp"
#include "causal/pipeline/input_screen.hpp"
#include "causal/pipeline/structured_factor_stream.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

using causal::pipeline::RowMajorMatrix;

constexpr Eigen::Index kFrame = 1024;
constexpr int kChannels = 4;
constexpr std::size_t kFrames = 64;  // distinct frames, fed in a cycle
constexpr double kPeriodNs = 1e9 / 20'480.0;

// kFrames consecutive frames of a stable 4-channel SVAR(1): y_k = sum_{j<k} b_kj y_j + sum_j a_kj y_j[n-1] + e_k,
// uniform noise (non-Gaussian, as sensor-sim's), fixed seed.
const std::vector<RowMajorMatrix>& frames() {
  static const std::vector<RowMajorMatrix> f = [] {
    std::mt19937_64 rng(36);
    std::uniform_real_distribution<double> unit(-std::sqrt(3.0), std::sqrt(3.0));
    const double b[kChannels][kChannels] = {{0, 0, 0, 0}, {0.3, 0, 0, 0}, {-0.2, 0.4, 0, 0}, {0, 0.25, -0.3, 0}};
    const double a[kChannels][kChannels] = {{0, 0.1, 0, 0}, {0, 0, -0.15, 0}, {0.2, 0, 0, 0.1}, {0, 0, 0.2, 0}};
    std::vector<RowMajorMatrix> out(kFrames, RowMajorMatrix(kFrame, kChannels));
    double prev[kChannels] = {0, 0, 0, 0};
    for (auto& m : out) {
      for (Eigen::Index i = 0; i < kFrame; ++i) {
        double y[kChannels];
        for (int k = 0; k < kChannels; ++k) {
          y[k] = 0.1 * unit(rng);
          for (int j = 0; j < k; ++j) y[k] += b[k][j] * y[j];
          for (int j = 0; j < kChannels; ++j) y[k] += a[k][j] * prev[j];
        }
        for (int k = 0; k < kChannels; ++k) m(i, k) = prev[k] = y[k];
      }
    }
    return out;
  }();
  return f;
}

const causal::pipeline::AssetPipelineParams& shipped_params() {
  static const causal::pipeline::AssetPipelineParams p =
      causal::pipeline::load_estimator_params(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/estimator.yaml");
  return p;
}

// The sample-level stream's parameters as AssetPipeline builds them for 4 channels (no graph configured).
causal::pipeline::FactorStreamParams sample_params() {
  causal::pipeline::FactorStreamParams p = shipped_params().sample;
  p.model.channels = kChannels;
  return p;
}

// Feeds frames in a cycle with the source's running indices (one group's continuous stream).
struct Cursor {
  std::uint64_t frame = 0;
  const RowMajorMatrix& rows() const { return frames()[frame % kFrames]; }
  std::uint64_t first_sample() const { return frame * static_cast<std::uint64_t>(kFrame); }
  std::int64_t first_time_ns() const { return 1'700'000'000'000'000'000LL + static_cast<std::int64_t>(first_sample() * 48'828); }
};

// Enough frames that every stage is past its calibration window (4096 samples of noise tuning, the screen's
// reference scale) and its first replay.
constexpr std::uint64_t kWarmupFrames = 16;

void whole(benchmark::State& state) {
  causal::pipeline::AssetPipeline pipe(shipped_params());
  causal::pipeline::PipelineOutput out;
  Cursor c;
  auto feed = [&] {
    out.clear();
    const auto check = pipe.feed_frame(c.rows(), c.first_sample(), c.frame / 20, c.frame == 0, false, false,
                                       c.first_time_ns(), 20'480.0, out);
    if (!check.ok) state.SkipWithError(check.problem.c_str());
    ++c.frame;
  };
  while (c.frame < kWarmupFrames) feed();
  for (auto _ : state) {
    feed();
    benchmark::DoNotOptimize(out.sample_reports.data());
  }
}

void copy(benchmark::State& state) {
  RowMajorMatrix buffer;
  Cursor c;
  for (auto _ : state) {
    buffer = c.rows();
    benchmark::DoNotOptimize(buffer.data());
    benchmark::ClobberMemory();
    ++c.frame;
  }
}

void screen(benchmark::State& state) {
  causal::pipeline::InputScreen screen(shipped_params().frame_screen, kChannels, causal::pipeline::ScreenLevel::Sample);
  std::vector<causal::pipeline::QualityEvent> events;
  RowMajorMatrix buffer;
  Cursor c;
  auto run = [&] {
    events.clear();
    buffer = c.rows();  // screened in place, as feed_frame does: the copy is counted here too
    screen.continue_at(c.first_sample());
    screen.screen(buffer.data(), static_cast<std::size_t>(buffer.rows()), events);
    ++c.frame;
  };
  while (c.frame < kWarmupFrames) run();
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(buffer.data());
  }
  if (!events.empty()) state.SkipWithError(("the screen judged clean frames: " + events.front().reason).c_str());
}

void sample(benchmark::State& state) {
  causal::pipeline::StructuredFactorStream stream(sample_params(), shipped_params().sample_structure);
  std::vector<causal::pipeline::FactorReport> out;
  Cursor c;
  auto feed = [&] {
    out.clear();
    stream.feed(c.rows(), c.first_sample(), c.frame == 0, c.first_time_ns(), kPeriodNs, out);
    ++c.frame;
  };
  while (c.frame < kWarmupFrames) feed();
  for (auto _ : state) {
    feed();
    benchmark::DoNotOptimize(out.data());
  }
}

void condition(benchmark::State& state) {
  causal::pipeline::ConditionStream stream(shipped_params().condition, kChannels);
  std::vector<causal::pipeline::ConditionSample> out;
  Cursor c;
  for (auto _ : state) {
    out.clear();
    const RowMajorMatrix& m = c.rows();
    stream.feed(m.data(), static_cast<std::size_t>(m.rows()), c.first_sample(), c.frame / 20, c.frame == 0, false,
                c.first_time_ns(), kPeriodNs, out);
    benchmark::DoNotOptimize(out.data());
    ++c.frame;
  }
}

void BM_FramePath(benchmark::State& state) {
  switch (state.range(0)) {
    case 0: whole(state); break;
    case 1: copy(state); break;
    case 2: screen(state); break;
    case 3: sample(state); break;
    default: condition(state); break;
  }
  state.SetItemsProcessed(state.iterations() * kFrame);
}
BENCHMARK(BM_FramePath)->ArgName("stage")->DenseRange(0, 4);

// One group's start-up on the processing thread (no worker): frames fed until the sample level has tuned its
// noise and replayed its window (the first frame after 4096 samples), i.e. 5 frames.
void BM_FramePathStartup(benchmark::State& state) {
  const std::uint64_t frames_needed = shipped_params().sample.noise.calibration_samples / kFrame + 1;
  for (auto _ : state) {
    causal::pipeline::AssetPipeline pipe(shipped_params());
    causal::pipeline::PipelineOutput out;
    for (Cursor c; c.frame < frames_needed; ++c.frame) {
      out.clear();
      pipe.feed_frame(c.rows(), c.first_sample(), 0, c.frame == 0, false, false, c.first_time_ns(), 20'480.0, out);
    }
    if (pipe.sample_stream() == nullptr || !pipe.sample_stream()->calibrated()) state.SkipWithError("not calibrated");
    benchmark::DoNotOptimize(out.sample_reports.data());
  }
}
BENCHMARK(BM_FramePathStartup)->Unit(benchmark::kMillisecond);

}  // namespace
