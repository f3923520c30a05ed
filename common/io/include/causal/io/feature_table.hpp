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

}  // namespace causal::io
