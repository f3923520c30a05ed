// Robustness variants of IMS test 2: runs the alarm tuning never saw, built deterministically from
// the real 984-snapshot feature table (deploy/data/ims2-features/merged_dataset_BearingTest_2.csv) by injecting
// what other IMS-format recordings contain: time gaps with level shifts, operating-change steps on a healthy
// channel, a second sensor per bearing (8 channels), and a long run whose degradation shows only at the end.
//
// Every variant carries its ground truth (which rows are healthy, which channels belong to the failing
// bearing, where the injections are), so a test judges detectors against the construction, not against
// their own output. Same base table + same seed = byte-identical variant.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace causal::testing {

struct BaseRun {
  std::vector<std::string> channel_names;  // G (test 2: Bearing 1 .. Bearing 4)
  std::vector<std::int64_t> time_ns;       // N, UTC
  Eigen::MatrixXd values;                  // N x G, mean |x| per snapshot
  std::size_t healthy_end = 500;           // rows [0, healthy_end) are healthy (test 2: nothing wrong before 500)
  int failing_channel = 0;                 // 0-based (test 2: bearing 1's outer race fails at the end)
};

// Reads an IMS-format merged table (first column the time stamp, one column per channel).
BaseRun read_base_run(const std::string& merged_table_path);

struct Injection {
  std::size_t row = 0;       // first variant row affected
  int channel = -1;          // -1 = every channel
  double factor = 1.0;       // multiplicative level change from this row on (1.0 = none)
  std::int64_t gap_ns = 0;   // extra time inserted before this row (0 = none)
};

struct Variant {
  std::string name;                        // gaps, steps, eight_channels, stretched, unchanged
  std::string description;                 // one line: what was injected
  std::vector<std::string> channel_names;
  std::vector<std::int64_t> time_ns;       // strictly increasing
  Eigen::MatrixXd values;                  // N x G, all finite and > 0
  std::vector<std::size_t> source_row;     // N: the base row each variant row was built from
  std::size_t healthy_end = 0;             // rows [0, healthy_end) are healthy: any alarm there is false
  std::vector<int> failing_channels;       // 0-based channels of the failing bearing
  std::vector<Injection> injections;       // what was done, in row order
};

// (a) Gaps of hours and days; after each gap every channel's level changes by its own factor in
// [1.15, 1.20] (cumulative), as when a rig is restarted after maintenance. Gaps lie in the healthy part.
Variant make_gaps_variant(const BaseRun& base, std::uint64_t seed);
// (b) Operating changes: two healthy channels (not the failing one) step up by a factor in [1.20, 1.40] at
// once and stay there, both in the healthy first half.
Variant make_steps_variant(const BaseRun& base, std::uint64_t seed);
// (c) Eight channels: two sensors per bearing, "Bearing 1 C1", "Bearing 1 C2", ...; C1 is the base value,
// C2 the base value times exp(N(0, 0.01^2)) drawn independently per snapshot (a second sensor on the same
// bearing sees the same level with its own small noise).
Variant make_eight_channel_variant(const BaseRun& base, std::uint64_t seed);
// (c') (c) on top of (a): 8 channels, both sensors of a bearing stepping with the bearing after each gap
// (Run A). Not part of make_all_variants (its table is the original one); the suite adds it.
Variant make_eight_channel_gaps_variant(const BaseRun& base, std::uint64_t seed);
// (d) Stretched to `total_rows` snapshots by walking back and forth through the healthy part (so every
// step continues the previous level: no jump at a join), each repeated row times exp(N(0, 0.005^2)); time
// stamps continue at the base interval; the base's degrading part follows unchanged at the end.
Variant make_stretched_variant(const BaseRun& base, std::uint64_t seed, std::size_t total_rows = 6000);
// A copy of the base run under `name`: every row its own source row, the base's healthy end and failing channel;
// the variants start from it. The base is checked first (shapes agree, a healthy part of at least 450 rows, the
// failing channel in range): std::invalid_argument otherwise.
Variant copy_of_base(const BaseRun& base, const std::string& name);
// (e) The base run itself.
Variant make_unchanged_variant(const BaseRun& base);

// (f) Wide asset group: every base channel copied `copies` times, channel-major ("Bearing 1 C1" ..
// "Bearing 1 C<copies>", "Bearing 2 C1", ...). Copy c (0-based) of channel j at row i is
// base(i, j) x (1 + 0.1 c) x (1 + noise N(0, 1)), one draw per cell (copy 0 included), so a group of G x copies
// channels where several sensors see the same bearing at their own gain and noise. noise = 0.03 is the 3 %
// of the wide-group runs in docs/results-ims.md. failing_channels = every copy of the base's failing
// channel. Refuses copies < 1, noise < 0 or >= 0.2 (a cell could turn non-positive).
Variant make_replicated_variant(const BaseRun& base, int copies, std::uint64_t seed, double noise = 0.03);

// All five, in the order above.
std::vector<Variant> make_all_variants(const BaseRun& base, std::uint64_t seed);

// Writes the variant in the base's IMS merged-table format: header ",<name 1>,<name 2>,...", then
// "YYYY-MM-DD hh:mm:ss,<v1>,..." with every value at full precision (17 significant digits).
void write_variant_csv(const Variant& v, const std::string& path);

}  // namespace causal::testing
