// Throughput of the estimators in sample-vectors per second (items/s): one item = one G-channel sample.
// Configurations (G channels, M lags): factors per outcome d = (G-1)(M+1):
//   G=4 M=1: d=6 (24 factors)   G=8 M=1: d=14 (112)   G=4 M=3: d=12 (48)   G=8 M=3: d=28 (224)
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <random>

#include "causal/estimation/batch_estimation.hpp"
#include "causal/estimation/fixed_lag_smoother.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"

namespace {

using causal::estimation::NoiseParams;

causal::estimation::SvarLayout make_layout(benchmark::State& state) {
  causal::estimation::ModelSpec spec;
  spec.channels = static_cast<int>(state.range(0));
  spec.lag_order = static_cast<int>(state.range(1));
  return causal::estimation::SvarLayout(spec);
}

Eigen::MatrixXd random_samples(Eigen::Index n, int g) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd y(n, g);
  for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] = normal(rng);
  return y;
}

const std::vector<causal::estimation::NoiseParams> kNoise = {causal::estimation::NoiseParams{1e-5, 1e-2, 1.0}};

// Streaming filter: SvarKalmanFilter::step on row-major samples.
void BM_FilterStep(benchmark::State& state) {
  const causal::estimation::SvarLayout layout = make_layout(state);
  const int g = layout.channels();
  constexpr int kRows = 4096;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> y = random_samples(kRows, g);
  causal::estimation::SvarKalmanFilter filter(layout, kNoise);
  int n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(filter.step(y.row(n).data()));
    n = (n + 1) % kRows;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["factors"] = layout.total_factors();
}

// A batch estimator (run_filter, run_rts_smoother) over 20000 samples with all its outputs.
template <typename Run>
void batch(benchmark::State& state, Run run_batch) {
  const causal::estimation::SvarLayout layout = make_layout(state);
  constexpr int kRows = 20000;
  const Eigen::MatrixXd y = random_samples(kRows, layout.channels());
  for (auto _ : state) {
    causal::estimation::EstimationRun run = run_batch(layout, kNoise, y);
    benchmark::DoNotOptimize(run.estimates.data());
  }
  state.SetItemsProcessed(state.iterations() * kRows);
}

// Batch filter with all outputs (estimates, std devs, innovations): run_filter.
void BM_RunFilter(benchmark::State& state) {
  batch(state, [](const auto& layout, const auto& noise, const auto& y) {
    return causal::estimation::run_filter(layout, noise, y);
  });
}

// Streaming fixed-lag smoother, L = state.range(2), releasing every state.range(3)-th sample (1 = every
// sample; causal-estimator releases one per publication, 1024 at sample level), allocation-free step_into.
void BM_FixedLagStep(benchmark::State& state) {
  const causal::estimation::SvarLayout layout = make_layout(state);
  const int g = layout.channels();
  constexpr int kRows = 4096;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> y = random_samples(kRows, g);
  causal::estimation::FixedLagSmoother smoother(layout, kNoise, static_cast<int>(state.range(2)),
                                   static_cast<std::uint64_t>(state.range(3)));
  Eigen::VectorXd est(layout.total_factors()), sd(layout.total_factors());
  std::uint64_t index = 0;
  int n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(smoother.step_into(y.row(n).data(), false, &index, est.data(), sd.data()));
    n = (n + 1) % kRows;
  }
  state.SetItemsProcessed(state.iterations());
}

// Batch RTS smoother with covariances: run_rts_smoother.
void BM_RunRts(benchmark::State& state) {
  batch(state, [](const auto& layout, const auto& noise, const auto& y) {
    return causal::estimation::run_rts_smoother(layout, noise, y);
  });
}

void configs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"G", "M"});
  for (auto gm : {std::pair{4, 1}, std::pair{8, 1}, std::pair{4, 3}, std::pair{8, 3}}) b->Args({gm.first, gm.second});
}

void lag_configs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"G", "M", "L", "every"});
  for (auto gm : {std::pair{4, 1}, std::pair{8, 1}, std::pair{4, 3}, std::pair{8, 3}}) {
    b->Args({gm.first, gm.second, 50, 1});
  }
  // The shipped sample level: lag 16, one release per 1024 samples, against releasing every sample.
  b->Args({4, 1, 16, 1});
  b->Args({4, 1, 16, 1024});
  b->Args({8, 1, 16, 1024});
  b->Args({4, 1, 64, 1024});
}

}  // namespace

BENCHMARK(BM_FilterStep)->Apply(configs);
BENCHMARK(BM_RunFilter)->Apply(configs)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FixedLagStep)->Apply(lag_configs);
BENCHMARK(BM_RunRts)->Apply(configs)->Unit(benchmark::kMillisecond);
