// Month-long simulated IMS-format recordings: the false-alarm budget of the alarm engine on long
// healthy runs and its detection delay on accelerating faults, against the robust-z reference detector.
//
// Log level of sensor s of bearing b at row t (10-minute snapshots):
//   base_b + drift_b * t / rows                   slow healthy drift, drift_b in [-6 %, +8 %] over the run
// + A_b sin(2 pi t / 144 + phi)                    daily cycle, A_b in [1 %, 2 %], one phase for the machine
// + load(t)                                         machine-wide load wander, AR(1) phi 0.99, sd 1 %
// + wander_b(t)                                     bearing's own slow wander, AR(1) phi 0.97, sd 0.7 %
// + noise_s(t)                                      sensor noise, AR(1) phi 0.3, sd 1.2 %
// Spread without drift and steps: sd ~1.9 % per snapshot, the healthy month's excursions of the median of 5
// reach +5-7 % (as the healthy half of Run B: +4 to +7 %); IMS test 2's healthy bearings: 1.0-1.8 %.
// + steps and gap re-levels (cumulative, from their row on) + spikes (one row) + the fault (bearing 0).
// Injections: 3 recording gaps (4-6 h, 2 days, 30 h), each followed by a level step of x[1.15, 1.20] per
// channel; 2 single-bearing operating steps of x[1.20, 1.40] on healthy bearings; one single-snapshot spike
// per day on a random channel, x[1.5, 3.0] (+34 to +92 sensor-noise sigma). Fault (optional): bearing 0's
// log level rises by ln(4) (exp(4 tau / T) - 1) / (e^4 - 1), tau rows after fault_start: x1.18 at T/2,
// x1.64 at 3T/4, x4 at T, accelerating like bearing wear; the run ends 24 rows after T.
// Every row before healthy_end is healthy by construction. Same options + seed = the same run.
#pragma once

#include <cstddef>
#include <cstdint>

#include "ims_variants.hpp"

namespace causal::testing {

struct MonthOptions {
  int bearings = 4;
  int sensors_per_bearing = 1;      // 2 -> 8 channels "Bearing b C1/C2" (a second sensor per bearing)
  std::size_t rows = 4320;          // healthy run: 30 days of 10-minute snapshots
  bool fault = false;               // accelerating fault of bearing 0 (then rows = fault_start + T + 24)
  std::size_t fault_start = 3600;
  std::size_t fault_rows_to_x4 = 720;  // T: 5 days from onset to 4x
  // Healthy wander beyond the above (0 = none, the runs stay byte-identical; drawn from their own generator):
  // slow_wander = amplitude A (log units) of each bearing's own slow wander A sin(2 pi t / P_b + phi_b), P_b in
  // [3, 8] days: ln(1.10) = +-10 %; short_excursions = that many single excursions of x[1.15, 1.25] on one random
  // channel for 2-4 snapshots, spread over the healthy rows (a few snapshots of an unusual load).
  double slow_wander = 0.0;
  int short_excursions = 0;
};

Variant make_month_variant(const MonthOptions& options, std::uint64_t seed);

// Rows after fault_start at which the fault alone first reaches `ratio` (e.g. 1.10): the yardstick of a
// detection delay.
double fault_rows_to_ratio(const MonthOptions& options, double ratio);

}  // namespace causal::testing
