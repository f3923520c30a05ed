// sensor-replay's parameters: one plain struct, filled and checked by parse_replay_options().
#pragma once

#include "causal/dds/service_runtime.hpp"
#include "causal/dds/source_driver.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace causal::replay {

enum class SourceKind { ImsDirectory, ChannelCsv, FeatureTable };

struct ReplayOptions {
  dds::CommonOptions dds;
  SourceKind source = SourceKind::ImsDirectory;
  std::string path;                       // directory or file
  std::string asset_group = "ims2-shaft1";
  std::vector<int> channels;              // 1-based selection; empty = all
  std::vector<std::string> channel_names; // names for the selected channels; empty = from the source
  std::string unit = "V";
  double sample_rate_hz = 20000.0;        // raw sources (IMS is 20 kHz)
  int frame_samples = 1024;               // samples per channel per frame
  double speed = 0.0;                     // plant seconds per wall second; 0 = as fast as possible
  std::size_t first_snapshot = 0;         // skip this many snapshots
  std::size_t max_snapshots = 0;          // 0 = all
  std::string feature_suffix;             // feature tables: column suffix ("_rms"); "" = every column, or the
                                          // feature_name columns of a <channel>_<feature> table (derived style)
  std::string feature_name = "meanabs";   // feature tables: what the values are
  double gap_factor = 3.0;                // feature tables: an interval > gap_factor x the median interval is a
                                          // time gap; the row after it is published as a discontinuity
  dds::SourceWaitOptions wait;           // readers waited for before publishing and whenever they go away (a
                                          // restarted estimator gets what it had not processed again)
  double progress_every_s = 5.0;
};

// Parses argv. Returns nullopt after printing --help / an error; `exit_code` tells the caller what to return.
[[nodiscard]] std::optional<ReplayOptions> parse_replay_options(int argc, char** argv, int& exit_code);

}  // namespace causal::replay
