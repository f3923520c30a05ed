#include "run_to_failure_sim.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace causal::prognosis_eval {

namespace {

constexpr double kNsPerHour = 3.6e12;
constexpr double kSpacingHours = 1.0 / 6.0;
constexpr std::int64_t kStart = 1704067200LL * 1000000000LL;  // 2024-01-01T00:00:00Z

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * std::generate_canonical<double, 53>(rng);
}

double noise(std::mt19937_64& rng, bool gaussian, double sd) {
  if (gaussian) return sd * std::normal_distribution<double>(0.0, 1.0)(rng);
  return uniform(rng, -std::sqrt(3.0) * sd, std::sqrt(3.0) * sd);
}

constexpr double kCatchUpHours = 1.0;

// The episodic clock: it stands at the last episode end a_k for the hold, then runs up to the next end a_{k+1}
// in the last kCatchUpHours before it, so the level w(s(tau)) is flat and then catches up with the smooth path.
double episodic_clock(const std::vector<double>& ends, double tau) {
  double start = 0.0;
  for (const double end : ends) {
    if (tau < end) {
      const double ramp = std::max(0.0, tau - (end - kCatchUpHours)) / kCatchUpHours;
      return start + ramp * (end - start);
    }
    start = end;
  }
  return tau;
}

}  // namespace

std::int64_t SimRun::crossing_ns(double ratio) const {
  double tau = std::log1p(std::log(ratio) / c) / lambda;
  double start = 0.0;
  for (const double end : episode_ends_h) {  // episodic: the catch-up during which s(tau) passes tau
    if (tau <= end) {
      tau = end - kCatchUpHours + kCatchUpHours * (tau - start) / (end - start);
      break;
    }
    start = end;
  }
  return onset_ns + static_cast<std::int64_t>(std::llround(tau * kNsPerHour));
}

SimRun simulate_run_to_failure(const SimSpec& spec) {
  std::mt19937_64 rng(spec.seed * 0x9E3779B97F4A7C15ULL + 17);
  SimRun run;
  run.noise_std = uniform(rng, 0.01, 0.03);
  const double tau_stop = uniform(rng, 40.0, 120.0);
  const double convexity = uniform(rng, 1.5, 5.0);
  run.lambda = convexity / tau_stop;
  run.c = std::log(spec.stop_ratio) / std::expm1(convexity);
  // Gaps: two before the onset (with level steps), one after it (none).
  const int gap_row_1 = static_cast<int>(uniform(rng, 150, 280)), gap_row_2 = static_cast<int>(uniform(rng, 300, 450));
  const double gap_hours_1 = uniform(rng, 24, 72), gap_hours_2 = uniform(rng, 24, 72);
  const double step_1 = uniform(rng, 0.15, 0.20), step_2 = uniform(rng, 0.15, 0.20);
  const double late_gap_tau = uniform(rng, 0.1, 0.6) * tau_stop, late_gap_hours = uniform(rng, 2, 12);
  const double base0 = 0.06, base1 = 0.045;
  if (spec.episodic) {  // a separate stream: the smooth runs' draws stay as they were
    std::mt19937_64 episodes(spec.seed * 0xD1B54A32D192ED03ULL + 29);
    for (double end = 0.0; end < 3.0 * tau_stop;) run.episode_ends_h.push_back(end += uniform(episodes, 4.0, 24.0));
  }
  double gain = 1.0, t_hours = 0.0;
  bool late_gap_done = !spec.gaps;
  for (int row = 0;; ++row) {
    bool discontinuity = false;
    if (row > 0) t_hours += kSpacingHours;
    if (spec.gaps && (row == gap_row_1 || row == gap_row_2)) {
      t_hours += row == gap_row_1 ? gap_hours_1 : gap_hours_2;
      gain *= 1.0 + (row == gap_row_1 ? step_1 : step_2);
      discontinuity = true;
    }
    if (row == spec.healthy_rows) run.onset_ns = kStart + static_cast<std::int64_t>(std::llround(t_hours * kNsPerHour));
    double tau = row >= spec.healthy_rows ? (t_hours * kNsPerHour - static_cast<double>(run.onset_ns - kStart)) / kNsPerHour
                                          : 0.0;
    if (!late_gap_done && tau >= late_gap_tau) {
      t_hours += late_gap_hours;
      tau += late_gap_hours;
      discontinuity = true;
      late_gap_done = true;
    }
    const double clock = spec.episodic ? episodic_clock(run.episode_ends_h, tau) : tau;
    const double w = row >= spec.healthy_rows ? run.c * std::expm1(run.lambda * clock) : 0.0;
    const double stop_w = std::log(spec.stop_ratio);
    const double sd0 = run.noise_std * (1.0 + 2.0 * std::min(w, stop_w) / stop_w);
    double y0 = std::log(base0 * gain) + std::min(w, stop_w) + noise(rng, spec.gaussian, sd0);
    const double y1 = std::log(base1 * gain) + noise(rng, spec.gaussian, run.noise_std);
    if (spec.spikes && row >= spec.healthy_rows && uniform(rng, 0, 1) < 0.01) y0 += std::log(1.5);
    run.time_ns.push_back(kStart + static_cast<std::int64_t>(std::llround(t_hours * kNsPerHour)));
    run.discontinuity.push_back(discontinuity);
    run.features.conservativeResize(row + 1, 2);
    run.features(row, 0) = std::exp(y0);
    run.features(row, 1) = std::exp(y1);
    if (w >= stop_w) break;  // the machine is stopped at the first snapshot at or above the stop level
  }
  run.stop_ns = run.time_ns.back();
  return run;
}

}  // namespace causal::prognosis_eval
