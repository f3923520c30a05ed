// Per-snapshot condition feature tables (one row per snapshot, one column per channel).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace causal::io {

struct FeatureTable {
  std::vector<std::string> channel_names;  // G
  std::vector<std::int64_t> time_ns;       // N, strictly increasing
  Eigen::MatrixXd values;                  // N x G
};

// Reads a comma-separated feature table (same CSV dialect as channel_csv.hpp).
//
// Time column: the first column whose header is "timestamp" or "time" (any case), else the first
// column. Cells are parsed with parse_utc(): "YYYY-MM-DD hh:mm:ss" or "YYYY.MM.DD.hh.mm.ss".
//
// column_suffix empty (merged_dataset style, e.g. ",Bearing 1,Bearing 2,..."): every other column is a
//   channel, except columns named file / index / n / time / timestamp (bookkeeping columns).
// column_suffix e.g. "_rms" (derived_per_file_stats style): the channels are the columns whose header
//   ends with the suffix, in file order; channel name = header minus the suffix ("bearing1_rms" ->
//   "bearing1"). Other columns are not parsed at all.
//
// Throws InputError (file + line) for: missing file, no header, no channel column (or none with the
// suffix: the message lists the headers), ragged rows, bad time stamps, time not strictly increasing,
// non-numeric or non-finite values, no data rows.
FeatureTable read_feature_table(const std::string& path, const std::string& column_suffix = "");

// Several features per channel? For a table read with an empty suffix: when every channel column is named
// <channel>_<feature> with a known condition feature (meanabs, rms, kurtosis, peak, peakabs, min, max, mean,
// std, skewness, crest) and there are at least two distinct features (derived_per_file_stats style), returns
// "_" + feature, the suffix that selects one feature's columns; throws std::invalid_argument naming the table's
// features when `feature` is not among them. Otherwise (a merged table: one column per channel, any names,
// e.g. "Bearing 1 C1" or "pump_in") returns "". So a table can be taken as it is, without per-file flags.
std::string per_feature_suffix(const FeatureTable& all_columns, const std::string& feature);

}  // namespace causal::io
