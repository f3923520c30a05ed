#include "replay_options.hpp"

#include "causal/io/name_limits.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <utility>
#include <vector>

namespace causal::replay {

std::optional<ReplayOptions> parse_replay_options(int argc, char** argv, int& exit_code) {
  ReplayOptions o;
  CLI::App app{
      "sensor-replay: publishes vibration frames (or per-snapshot condition features) on DDS from recordings.\n"
      "It is also the template for a real sensor publisher: a sensor driver replaces the file source and keeps\n"
      "the same topic, type and QoS profile."};
  dds::add_common_options(app, o.dds);
  std::string ims_dir, csv_file, feature_file;
  auto* src = app.add_option_group("source", "exactly one data source");
  src->add_option("--ims-dir", ims_dir,
                  "IMS directory: one tab-separated file per snapshot named YYYY.MM.DD.hh.mm.ss (.gz allowed), one "
                  "column per channel; publishes raw frames")
      ->check(CLI::ExistingDirectory);
  src->add_option("--csv", csv_file, "CSV of channels (header row of names, one row per sample); publishes raw frames")
      ->check(CLI::ExistingFile);
  src->add_option("--features", feature_file,
                  "per-snapshot condition-feature table (timestamp, then one column per channel), e.g. "
                  "merged_dataset_BearingTest_2.csv; publishes condition vectors")
      ->check(CLI::ExistingFile);
  src->require_option(1);
  app.add_option("--asset-group", o.asset_group, "asset-group id (the DDS key; 1 to 255 bytes)")->capture_default_str();
  app.add_option("--channels", o.channels, "1-based channels to publish, e.g. --channels 1 2 3 4 (default: all)")
      ->check(CLI::PositiveNumber);
  app.add_option("--channel-names", o.channel_names,
                 "names for the published channels, 1 to 255 bytes each (default: from the source)");
  app.add_option("--unit", o.unit, "engineering unit of raw samples")->capture_default_str();
  app.add_option("--sample-rate", o.sample_rate_hz, "sampling rate of raw sources, Hz")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--frame-samples", o.frame_samples, "samples per channel in one frame")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  app.add_option("--speed", o.speed,
                 "plant seconds per wall-clock second: 1 = real time, 600 = ten minutes of plant time per second, "
                 "0 = as fast as possible")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--first-snapshot", o.first_snapshot, "skip this many snapshots (rows for feature tables)")
      ->capture_default_str();
  app.add_option("--max-snapshots", o.max_snapshots, "publish at most this many snapshots (0 = all)")
      ->capture_default_str();
  app.add_option("--feature-suffix", o.feature_suffix,
                 "feature tables (optional): take the columns ending in this suffix (e.g. _rms in "
                 "derived_per_file_stats_all984.csv); default: every column of a merged table (timestamp, one column "
                 "per channel, any names), or the --feature-name columns of a table whose columns are "
                 "<channel>_<feature> for several features")
      ->capture_default_str();
  app.add_option("--feature-name", o.feature_name,
                 "feature tables (optional): name of the feature (rms, meanabs, kurtosis, peak); IMS merged tables "
                 "hold mean |x| per snapshot")
      ->capture_default_str();
  app.add_option("--gap-factor", o.gap_factor,
                 "feature tables: a time interval longer than this many median intervals is a gap (a stopped "
                 "recorder); the row after it is published as a discontinuity and logged")
      ->check(CLI::Range(1.0, 1e9))
      ->capture_default_str();
  dds::add_source_wait_options(app, o.wait, true);
  app.add_option("--progress-every", o.progress_every_s, "seconds between progress lines")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e);
    if (exit_code != 0) exit_code = 2;  // a usage error, as documented (never CLI11's own codes)
    return std::nullopt;
  }
  if (!ims_dir.empty()) {
    o.source = SourceKind::ImsDirectory;
    o.path = ims_dir;
  } else if (!csv_file.empty()) {
    o.source = SourceKind::ChannelCsv;
    o.path = csv_file;
  } else {
    o.source = SourceKind::FeatureTable;
    o.path = feature_file;
  }
  // The one name limit (causal/io/name_limits.hpp), at the edge: a name no reader would take is a usage error.
  std::vector<std::pair<const char*, const std::string*>> names{{"--asset-group", &o.asset_group}};
  if (!feature_file.empty()) names.emplace_back("--feature-name", &o.feature_name);
  for (const auto& n : o.channel_names) names.emplace_back("--channel-names", &n);
  for (const auto& [option, name] : names) {
    if (const char* problem = io::name_problem(*name)) {
      std::cerr << "error: " << option << " '" << name->substr(0, 40) << (name->size() > 40 ? "..." : "") << "' is "
                << problem << " (names are 1 to " << io::kMaxNameBytes << " bytes)\n";
      exit_code = 2;
      return std::nullopt;
    }
  }
  if (!o.channel_names.empty() && !o.channels.empty() && o.channel_names.size() != o.channels.size()) {
    std::cerr << "error: --channel-names has " << o.channel_names.size() << " names for " << o.channels.size()
              << " --channels\n";
    exit_code = 2;
    return std::nullopt;
  }
  exit_code = 0;
  return o;
}

}  // namespace causal::replay
