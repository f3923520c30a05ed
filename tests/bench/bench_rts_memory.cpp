// Peak resident memory of the batch estimators on a long record: a plain program, not a
// Google Benchmark, because peak RSS (getrusage ru_maxrss) is per process and only ever grows.
//
//   causal_bench_rts_memory [rows = 1000000] [rts|filter|fixed-lag] [every = 1]
//
// Prints the peak RSS after the simulated data exists and after the estimator ran; the difference is what
// the estimator needed (outputs included: 2 * 24 doubles per kept row for G = 4, M = 1; with every > 1 the
// innovations are not stored).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "causal/estimation/batch_estimation.hpp"

namespace {

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in kB on Linux
}

}  // namespace

int main(int argc, char** argv) {
  const long rows = argc > 1 ? std::atol(argv[1]) : 1000000;
  const std::string estimator = argc > 2 ? argv[2] : "rts";
  const long every = argc > 3 ? std::atol(argv[3]) : 1;
  if (rows < 2 || every < 1 || (estimator != "rts" && estimator != "filter" && estimator != "fixed-lag")) {
    std::fprintf(stderr, "usage: %s [rows >= 2] [rts|filter|fixed-lag] [every >= 1]\n", argv[0]);
    return 2;
  }
  causal::estimation::ModelSpec spec;  // G = 4, M = 1: 24 factors
  const causal::estimation::SvarLayout layout(spec);
  // A stable VAR(1) with one instantaneous chain; the values only need to be realistic, not known.
  Eigen::MatrixXd y(rows, 4);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> e(0.0, 1.0);
  double prev[4] = {0, 0, 0, 0};
  for (long n = 0; n < rows; ++n) {
    const double y0 = 0.5 * prev[0] + e(rng);
    const double y3 = 0.6 * y0 + 0.3 * prev[3] + e(rng);
    const double y2 = 0.4 * y3 - 0.2 * prev[1] + e(rng);
    const double y1 = 0.3 * y0 + 0.5 * y2 + 0.2 * prev[2] + e(rng);
    y(n, 0) = prev[0] = y0;
    y(n, 1) = prev[1] = y1;
    y(n, 2) = prev[2] = y2;
    y(n, 3) = prev[3] = y3;
  }
  const double before = peak_rss_mb();
  const std::vector<causal::estimation::NoiseParams> noise = {{1e-6, 1.0, 1.0}};
  const causal::estimation::BatchOutput out{every, every == 1};  // decimated: only the factors are wanted
  const auto t0 = std::chrono::steady_clock::now();
  causal::estimation::EstimationRun run;
  if (estimator == "rts") run = causal::estimation::run_rts_smoother(layout, noise, y, {}, out);
  if (estimator == "filter") run = causal::estimation::run_filter(layout, noise, y, {}, out);
  if (estimator == "fixed-lag") run = causal::estimation::run_fixed_lag_smoother(layout, noise, y, {}, 50, out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double after = peak_rss_mb();
  std::printf("%s rows=%ld every=%ld kept_rows=%ld: peak RSS with data %.1f MB, after the estimator %.1f MB "
              "(estimator +%.1f MB), %.2f s, x[last kept][0]=%.6f\n",
              estimator.c_str(), rows, every, static_cast<long>(run.estimates.rows()), before, after, after - before,
              seconds, run.estimates(run.estimates.rows() - 1, 0));
  return 0;
}
