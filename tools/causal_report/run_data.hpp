// A causal-recorder folder, read back: which assets it holds and, per asset, the condition trends,
// the condition-level factor trajectories (filter / fixed-lag) and the alarms. Times are UTC seconds
// since the Unix epoch (what gnuplot's time axis takes); missing cells are NaN.
#pragma once

#include "causal/alarms/alarm_event.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace causal::report {

// Files of one asset (file-name component = sanitised asset id), found by name.
struct AssetFiles {
  std::string asset;                                     // sanitised id, as in the file names
  std::vector<std::pair<std::string, std::filesystem::path>> conditions;  // (feature, file)
  std::filesystem::path factors_filter, factors_fixed_lag;  // condition level; empty when absent
};

struct RunFiles {
  std::vector<AssetFiles> assets;   // sorted by id; includes assets known only from alarms.csv
  std::filesystem::path alarms;     // empty when absent
  std::size_t csv_count = 0;        // recorder CSVs found (conditions, factors of any scale, alarms)
};

// Lists the folder. Assets are also taken from alarms.csv (asset_group, sanitised).
// Throws std::runtime_error when the folder cannot be read or a CSV is malformed.
RunFiles discover_run(const std::filesystem::path& run_dir);

struct ConditionSeries {
  std::string feature;
  std::vector<std::string> channels;
  std::vector<double> t;                    // N
  std::vector<std::vector<double>> values;  // per channel, N
};

struct FactorSeries {
  std::string kind;                    // "filter" | "fixed-lag"
  std::vector<double> t;               // N
  std::vector<std::string> names;      // F factor names, outcome-major
  std::vector<int> outcome;            // F: 0-based outcome of each factor
  std::vector<std::vector<double>> mean, sd;  // F x N
  std::vector<std::string> outcome_names;     // G, from the nis_ columns
};

// The alarm engine's severity and its one spelling (to_string, parse_severity); the colour is the report's.
using alarms::Severity;
using alarms::parse_severity;
using alarms::to_string;
const char* severity_colour(Severity s);  // "#RRGGBB"

struct AlarmRecord {
  std::string alarm_id, state, kind, asset_group, channel_name, root_cause_name, reason;
  std::string category = "degradation";  // degradation, data_quality, health, operating_change (older files: none)
  std::optional<double> sample_index;     // snapshot / sample index of the evidence
  std::optional<double> root_cause_confidence;
  Severity severity = Severity::Advisory;
  int channel = 0, root_cause_channel = 0;  // 1-based, 0 = unknown
  std::optional<double> time, raised, cleared;  // seconds
  std::string raised_utc, cleared_utc;
};

// One alarm over its life: severity segments from raised to cleared (or the end of the data).
struct AlarmSpan {
  std::string alarm_id, kind, channel_name, root_cause_name;
  int channel = 0, root_cause_channel = 0;
  double raised = 0.0;
  std::optional<double> cleared;
  std::string raised_utc, cleared_utc;
  Severity first_severity = Severity::Advisory, max_severity = Severity::Advisory;
  struct Segment {
    double from = 0.0, to = 0.0;
    Severity severity = Severity::Advisory;
  };
  std::vector<Segment> segments;
};

// Parses a factor name of outcome-major models ("x12", "xL13", "xL2_10_3", "x10_2"): 1-based outcome k,
// source channel j and lag (0 = instantaneous). G resolves "xL210_2"-style ambiguity (k <= G).
struct FactorName {
  int outcome = 0, source = 0, lag = 0;
};
[[nodiscard]] std::optional<FactorName> parse_factor_name(const std::string& name, int channel_count);

ConditionSeries load_conditions(const std::filesystem::path& file, const std::string& feature);
FactorSeries load_factors(const std::filesystem::path& file, const std::string& kind);
// Rows of alarms.csv whose asset_group sanitises to `asset` (all rows when asset is empty).
std::vector<AlarmRecord> load_alarms(const std::filesystem::path& file, const std::string& asset);

// Groups alarm rows by id (in order of first appearance). Escalations without a time are not placed on
// the time axis but still raise max_severity. end_time closes spans that never cleared.
std::vector<AlarmSpan> build_alarm_spans(const std::vector<AlarmRecord>& rows, double end_time);

}  // namespace causal::report
