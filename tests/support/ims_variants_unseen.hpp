// Two IMS-format runs the alarm rules were not tuned on, rebuilt deterministically from IMS test 2's healthy
// rows (tests/support/ims_variants.hpp: same BaseRun, same Variant with its ground truth):
//
// relevelled_failure: 8 channels (two sensors per bearing, C2 = C1 x exp(N(0, 0.01^2))); a 6-day recording gap
//   at row 160 after which every channel stands x[1.20, 1.45] higher (its own factor; one channel at 1.44);
//   from row 340 bearing 1's C1 rises within 3 snapshots to x[1.50, 1.60] its post-gap level and holds there
//   for 60 snapshots (10 h) while C2 stands at x1.35; then a 1-hour recording gap and the last 4 snapshots at
//   x2.5, x2.8, x3.0, x3.3 (C1) and x1.8-2.2 (C2): a fast final failure. Rows [0, 340) are healthy.
// low_baseline_stretch: IMS test 2 itself (4 channels) with a healthy channel (Bearing 4) whose warm-up rows
//   (the first 20 snapshots) stand at its own level and whose baseline window (rows 20-139) sits in a low
//   stretch 8 % below it; from row 140 it wanders back within 30 snapshots to its earlier level, with one
//   excursion of +20 % for 4 snapshots at row 300. Rows [0, 500) are healthy (bearing 1 fails at the end).
#pragma once

#include <cstdint>

#include "ims_variants.hpp"

namespace causal::testing {

Variant make_relevelled_failure_variant(const BaseRun& base, std::uint64_t seed);
Variant make_low_baseline_stretch_variant(const BaseRun& base);

// Rows of relevelled_failure (for the tests' assertions).
struct RelevelledFailureRows {
  std::size_t first_gap = 160;      // first row after the 6-day gap
  std::size_t rise = 340;           // first row of bearing 1 C1's rise (= healthy_end)
  std::size_t plateau_end = 403;    // first row after the plateau (3 rows of rise + 60 of plateau)
  std::size_t final_rows = 4;       // rows after the short gap (the last rows of the run)
};

}  // namespace causal::testing
