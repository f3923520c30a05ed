// Throughput of one asset group's sample-level FactorStream (what causal-estimator runs per asset group):
// Kalman filter plus the fixed-lag smoother at lag L, one report per 1024 samples, fixed noise, fed in
// 2048-sample frames like an IMS replay. Items = G-channel sample vectors; an IMS asset group needs 20,480/s.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "causal/pipeline/asset_pipeline.hpp"
#include "causal/pipeline/factor_stream.hpp"
#include "causal/estimation/state_archive.hpp"
#include "../support/ims_condition_model.hpp"

namespace {

using causal::pipeline::RowMajorMatrix;

void BM_SampleLevelFactorStream(benchmark::State& state) {
  causal::pipeline::FactorStreamParams p;
  p.model.channels = 4;
  p.model.lag_order = 1;
  p.noise.fixed = causal::estimation::NoiseParams{1e-6, 1e-2, 1.0};
  p.publish_every = 1024;
  p.fixed_lag = static_cast<int>(state.range(0));
  causal::pipeline::FactorStream stream(p);
  constexpr Eigen::Index kFrame = 2048;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 0.1);
  RowMajorMatrix frame(kFrame, 4);
  for (Eigen::Index i = 0; i < frame.size(); ++i) frame.data()[i] = normal(rng);
  std::vector<causal::pipeline::FactorReport> out;
  std::int64_t t = 0;
  std::uint64_t index = 0;
  for (auto _ : state) {
    out.clear();
    stream.feed(frame, index, false, t, 50'000.0, out);
    t += kFrame * 50'000;
    index += kFrame;
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * kFrame);
}
BENCHMARK(BM_SampleLevelFactorStream)->ArgName("L")->Arg(0)->Arg(16)->Arg(64);

// Checkpoint of one IMS asset group (G = 4, both levels, the shipped estimator.yaml settings: automatic
// noise on 4096 samples, fixed lag 16, publish every 1024; condition level meanabs, fixed lag 6, centre +
// VAR-LiNGAM on 100 snapshots), after `snapshots` snapshots of 20,480 samples in 2048-sample frames
// (0: after one frame, i.e. inside the sample-level calibration window, the largest state). Reports
// the checkpoint size in bytes; the time is one save (to bytes) or one restore into a fresh pipeline.
causal::pipeline::AssetPipelineParams ims_params() {
  causal::pipeline::AssetPipelineParams p;
  p.sample.model.lag_order = 1;
  p.sample.noise.automatic = true;
  p.sample.noise.calibration_samples = 4096;
  p.sample.publish_every = 1024;
  p.sample.fixed_lag = 16;
  causal::test::set_ims_condition_model(p);
  return p;
}

std::unique_ptr<causal::pipeline::AssetPipeline> fed_ims_group(int snapshots) {
  auto pipe = std::make_unique<causal::pipeline::AssetPipeline>(ims_params());
  constexpr Eigen::Index kFrame = 2048, kSnapshot = 20'480;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 0.07);
  std::uniform_real_distribution<double> level(-0.2, 0.2);
  RowMajorMatrix frame(kFrame, 4);
  causal::pipeline::PipelineOutput out;
  const Eigen::Index frames = snapshots == 0 ? 1 : snapshots * (kSnapshot / kFrame);
  double amp[4] = {1, 1, 1, 1};
  for (Eigen::Index f = 0; f < frames; ++f) {
    const Eigen::Index pos = f % (kSnapshot / kFrame);
    if (pos == 0) {
      for (double& a : amp) a = std::exp(level(rng));
    }
    for (Eigen::Index i = 0; i < frame.rows(); ++i)
      for (int j = 0; j < 4; ++j) frame(i, j) = amp[j] * normal(rng);
    out.clear();
    pipe->feed_frame(frame, static_cast<std::uint64_t>(f * kFrame), static_cast<std::uint64_t>(f / 10), pos == 0,
                     pos == kSnapshot / kFrame - 1, false, static_cast<std::int64_t>(f) * 102'400'000, 20'480.0, out);
  }
  return pipe;
}

void BM_AssetPipelineCheckpointSave(benchmark::State& state) {
  const auto pipe = fed_ims_group(static_cast<int>(state.range(0)));
  std::size_t bytes = 0;
  for (auto _ : state) {
    causal::estimation::StateWriter w;
    pipe->save(w);
    bytes = w.bytes().size();
    benchmark::DoNotOptimize(w.bytes().data());
  }
  state.counters["bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_AssetPipelineCheckpointSave)->ArgName("snapshots")->Arg(0)->Arg(50)->Arg(110)->Unit(benchmark::kMicrosecond);

void BM_AssetPipelineCheckpointRestore(benchmark::State& state) {
  const auto pipe = fed_ims_group(static_cast<int>(state.range(0)));
  causal::estimation::StateWriter w;
  pipe->save(w);
  for (auto _ : state) {
    causal::pipeline::AssetPipeline fresh(ims_params());
    causal::estimation::StateReader r(w.bytes());
    fresh.restore(r);
    benchmark::DoNotOptimize(&fresh);
  }
  state.counters["bytes"] = static_cast<double>(w.bytes().size());
}
BENCHMARK(BM_AssetPipelineCheckpointRestore)->ArgName("snapshots")->Arg(0)->Arg(50)->Arg(110)->Unit(benchmark::kMicrosecond);

}  // namespace
