// The condition-level estimator's CPU per snapshot against the asset group's width: IMS test 2 with every
// bearing copied 1, 2, 4 and 5 times (4, 8, 16, 20 channels; tests/support make_replicated_variant, seed 32)
// through causal-estimator's AssetPipeline with the shipped deploy/config/estimator.yaml (input screen,
// structure calibration, centring, learned causal order, Kalman filter, fixed-lag smoother). No DDS: what
// one snapshot costs the estimator's filters. Prints one line per width (docs/scale-and-benchmarks.md,
// "Condition-level CPU per snapshot against the width"): the structure window and its blocks, the CPU of the
// calibration (learning the order, replaying the window), and the CPU per snapshot after it.
// --dense: the structure window raised to 10 x G x (M + 1) (one dense VAR-LiNGAM order, the rule before the
// per-block order) for comparison.
//   build/tests/bench/causal_bench_condition_width [--repeat N] [--dense]
#include "causal/pipeline/estimator_params.hpp"
#include "ims_variants.hpp"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Timing {
  double calibration_s = 0.0, steady_s = 0.0;
  std::size_t window = 0, steady = 0, blocks = 0;
  std::string order_source;
};

Timing run(const causal::pipeline::AssetPipelineParams& params, const causal::testing::Variant& v) {
  causal::pipeline::AssetPipeline pipe(params);
  causal::pipeline::PipelineOutput out;
  Timing t;
  for (Eigen::Index i = 0; i < v.values.rows(); ++i) {
    out.clear();
    const bool calibrating = pipe.condition_stream() == nullptr;
    const double t0 = cpu_seconds();
    const auto check = pipe.feed_condition(v.values.row(i).transpose(), static_cast<std::uint64_t>(i), i == 0,
                                           v.time_ns[static_cast<std::size_t>(i)], out);
    const double dt = cpu_seconds() - t0;
    if (!check.ok) {
      std::fprintf(stderr, "refused: %s\n", check.problem.c_str());
      std::exit(1);
    }
    if (calibrating) {
      t.calibration_s += dt;
      ++t.window;
    } else {
      t.steady_s += dt;
      ++t.steady;
    }
  }
  t.blocks = pipe.condition_structure()->blocks.size();
  t.order_source = pipe.condition_structure()->order_source;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  bool dense = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::printf("causal_bench_condition_width [--repeat N (3)] [--dense]: condition-level CPU per snapshot at 4, 8, 16 "
                  "and 20 channels (IMS test 2 replicated); --dense raises the structure window to 10 x G x (M + 1)\n");
      return 0;
    }
    if (a == "--dense") {
      dense = true;
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else {
      repeat = 0;
    }
  }
  if (repeat < 1) {
    std::fprintf(stderr, "usage: causal_bench_condition_width [--repeat N >= 1] [--dense]\n");
    return 2;
  }
  const std::string deploy = CAUSAL_TWIN_DEPLOY_DIR;
  auto params = causal::pipeline::load_estimator_params(deploy + "/config/estimator.yaml");
  const auto base = causal::testing::read_base_run(deploy + "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  std::printf("channels window blocks order calibration_cpu_ms steady_cpu_us_per_snapshot (best of %d)\n", repeat);
  for (const int copies : {1, 2, 4, 5}) {
    const auto v = causal::testing::make_replicated_variant(base, copies, 32);
    if (dense) {
      const auto g = static_cast<std::size_t>(v.values.cols());
      const auto m = static_cast<std::size_t>(params.condition_model.model.lag_order);
      params.condition_structure.calibration_samples = std::max<std::size_t>(100, 10 * g * (m + 1));
    }
    Timing best;
    for (int r = 0; r < repeat; ++r) {
      const Timing t = run(params, v);
      if (r == 0 || t.steady_s < best.steady_s) best = t;
    }
    std::printf("%8lld %6zu %6zu %-9s %18.1f %26.1f\n", static_cast<long long>(v.values.cols()), best.window, best.blocks,
                best.order_source.c_str(), 1e3 * best.calibration_s, 1e6 * best.steady_s / static_cast<double>(best.steady));
  }
  return 0;
}
