// IMS/NASA bearing data set: directory listing and snapshot reader.
// A snapshot file is named by its time stamp YYYY.MM.DD.hh.mm.ss (optionally + ".gz") and holds
// 20,480 rows x 4 (test 2) or 8 (test 1) whitespace-separated columns, no header.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace causal::io {

// "2004.02.12.10.32.39" or "2004.02.12.10.32.39.gz" (a leading directory is ignored) -> UTC ns since
// the epoch. nullopt for any other name or an impossible date/time.
[[nodiscard]] std::optional<std::int64_t> parse_ims_timestamp(std::string_view file_name);

struct ImsSnapshotInfo {
  std::string path;        // dir + "/" + name
  std::string name;        // file name as found, e.g. "2004.02.12.10.32.39.gz"
  std::int64_t time_ns;    // parsed from the name
  std::size_t index;       // 0-based position in the sorted listing (NOT the run index if files are missing)
};

struct ImsListing {
  std::vector<ImsSnapshotInfo> snapshots;  // sorted by time, strictly increasing
  std::vector<std::string> ignored;        // other entries' names (README, CSV, sub-folders, ...), sorted;
                                           // also the ".gz" twin when both "X" and "X.gz" exist
};

// Lists the snapshot files in dir (regular files or symlinks to them). Throws InputError(dir, 0, ...)
// if dir is missing / not a directory / unreadable or contains no snapshot file.
ImsListing list_ims_directory(const std::string& dir);

// Reads one snapshot, plain or gzip (detected from the content, not the name): N x G matrix.
// Whitespace separated (tabs or spaces), LF or CRLF endings, blank lines skipped, no header.
// expected_channels 0 = infer G from the first row. Throws InputError naming file and line for:
// unreadable/corrupt file, empty file, ragged rows (or a count != expected_channels), text in a number,
// non-finite values (nan/inf).
Eigen::MatrixXd read_ims_snapshot(const std::string& path, int expected_channels = 0);

}  // namespace causal::io
