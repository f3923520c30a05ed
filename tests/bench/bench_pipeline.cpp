// Throughput of one asset group's sample-level FactorStream (what causal-estimator runs per asset group):
// Kalman filter plus the fixed-lag smoother at lag L, one report per 1024 samples, fixed noise, fed in
// 2048-sample frames like an IMS replay. Items = G-channel sample vectors; an IMS asset group needs 20,480/s.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <random>
#include <vector>

#include "causal/pipeline/factor_stream.hpp"

namespace {

using causal::pipeline::RowMajorMatrix;

void BM_SampleLevelFactorStream(benchmark::State& state) {
  causal::pipeline::FactorStreamParams p;
  p.model.channels = 4;
  p.model.lag_order = 1;
  p.noise.fixed = causal::NoiseParams{1e-6, 1e-2, 1.0};
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

}  // namespace
