// Simulated run-to-failure condition series with known crossing times, for the prognosis unit tests and
// causal-prognosis-eval. Two channels at 10-minute spacing: channel 0 degrades from the onset on, channel 1
// stays healthy. Channel 0's log level above its (gain-adjusted) baseline follows the exponential degradation
// model of the remaining-useful-life literature, w(tau) = c (exp(lambda tau) - 1) for tau hours after the
// onset (accelerating wear), until it reaches log(stop_ratio): the machine is stopped there. Per seed: the
// noise level, the time from onset to stop and the convexity lambda * tau_stop are drawn; recording gaps
// (one to three days before the onset, each with a +15-20 % level step on both channels, as a sensor remount
// or a re-levelled plant after a stop gives; a few hours after the onset, no step: wear goes on in clock
// time); measurement noise on the log level, Gaussian or uniform, growing with the wear (a damaged bearing is
// noisier); and 1 % single-snapshot spikes (+50 %) on the degrading channel.
// Episodic (SimSpec::episodic): the same wear shows in episodes, as a bearing whose damage grows in steps does:
// the level holds for 4-24 h, then catches up with the smooth path w(tau) in one hour, and holds again (a clock
// s(tau) that stands still and then runs; w(s(tau))). Drawn from a separate stream, so every other draw, and
// every smooth run, is unchanged.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace causal::prognosis_eval {

struct SimSpec {
  std::uint64_t seed = 1;
  bool gaussian = true;          // else uniform noise of the same standard deviation
  int healthy_rows = 500;        // rows before the onset (the simulated plants: convex from row 500)
  double stop_ratio = 6.5;       // the run ends when channel 0 reaches this multiple of its baseline
  bool gaps = true;              // recording gaps (and the pre-onset level steps)
  bool spikes = true;
  bool episodic = false;         // wear in episodes: holds of 4-24 h, each ended by a 1-h catch-up
};

struct SimRun {
  std::vector<std::int64_t> time_ns;     // N, increasing (UTC, from 2024-01-01)
  std::vector<bool> discontinuity;       // N: first row after a recording gap
  Eigen::MatrixXd features;              // N x 2, positive (mean-abs-like levels)
  std::int64_t onset_ns = 0;
  std::int64_t stop_ns = 0;              // time of the last row
  double noise_std = 0.0, lambda = 0.0, c = 0.0;  // drawn parameters (per hour)
  std::vector<double> episode_ends_h;    // episodic: hours after the onset at which each hold's catch-up ends
  // Time at which channel 0's noise-free level reaches `ratio` x its baseline (w = log ratio).
  std::int64_t crossing_ns(double ratio) const;
};

SimRun simulate_run_to_failure(const SimSpec& spec);

}  // namespace causal::prognosis_eval
