// sensor-sim's parameters: one plain struct, filled and checked by parse_sim_options().
#pragma once

#include "causal/dds/service_runtime.hpp"
#include "causal/dds/source_driver.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace causal::sim {

struct SimOptions {
  dds::CommonOptions dds;
  int groups = 1;                          // simulated asset groups, ids <prefix>0000, <prefix>0001, ...
  std::string group_prefix = "sim-";
  int channels = 4;                        // G channels per group
  int lag_order = 1;                       // M of the simulated structural VAR
  std::uint64_t seed = 1;                  // same seed: same factors, same samples
  double rate_hz = 0.0;                    // samples per second per group (wall clock); 0 = as fast as possible
  double sample_rate_hz = 20000.0;         // stamped in the frames; time of sample i = start + i / sample_rate
  std::int64_t start_time_ns = 1767225600LL * 1000000000LL;  // 2026-01-01T00:00:00Z: time of sample 0
  int frame_samples = 1024;                // samples per channel in one frame
  // Latency benchmarks: sample 0 is stamped with the wall clock when publishing starts, so (paced at
  // --rate = --sample-rate) a frame's first_sample_time_ns is the wall-clock time it is due.
  bool wall_clock_stamps = false;
  // Paced runs: spread the groups' frames evenly over each frame period (group g of K is due g/K of a period
  // later, its sample times shifted alike) instead of publishing every group's frame at the same instant:
  // independent sensors are not phase-locked.
  bool stagger = false;
  std::uint64_t frames_per_group = 0;      // stop after this many frames per group (0 = no bound)
  double max_runtime_s = 0.0;              // stop after this many seconds in any case (0 = no bound)
  dds::SourceWaitOptions wait;             // the readers waited for before publishing
  double write_timeout_s = 10.0;           // a frame (condition vector) not accepted within this is counted lost
  // Condition-level plant mode (--plant; plant_node.hpp): plant kinds cycled over the groups, condition vectors
  // instead of frames, approved interventions obeyed.
  std::vector<std::string> plants;         // empty: the sample-level SVAR frames above
  std::uint64_t snapshots = 400;           // snapshots per group
  double snapshot_rate = 0.0;              // snapshots per second per group (wall clock); 0 = as fast as possible
  std::string plant_feature = "meanabs";   // feature name stamped in the condition vectors
  std::int64_t snapshot_seconds = 600;     // data time between snapshots
};

// Parses argv. Returns nullopt after printing --help / an error; `exit_code` tells the caller what to return.
[[nodiscard]] std::optional<SimOptions> parse_sim_options(int argc, char** argv, int& exit_code);

}  // namespace causal::sim
