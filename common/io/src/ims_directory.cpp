// IMS directory listing and file-name time stamps.
#include "causal/io/ims_directory.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "causal/io/input_error.hpp"
#include "causal/io/time_format.hpp"

namespace causal::io {

std::optional<std::int64_t> parse_ims_timestamp(std::string_view file_name) {
  const std::size_t slash = file_name.find_last_of('/');
  if (slash != std::string_view::npos) file_name.remove_prefix(slash + 1);
  constexpr std::string_view kGz = ".gz";
  if (file_name.size() > kGz.size() && file_name.substr(file_name.size() - kGz.size()) == kGz) {
    file_name.remove_suffix(kGz.size());
  }
  // Exactly "YYYY.MM.DD.hh.mm.ss": 19 characters, dots at fixed places (parse_utc checks digits/ranges).
  if (file_name.size() != 19 || file_name[4] != '.') return std::nullopt;
  return parse_utc(file_name);
}

ImsListing list_ims_directory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (ec || !fs::exists(st)) throw InputError(dir, 0, "directory does not exist");
  if (!fs::is_directory(st)) throw InputError(dir, 0, "not a directory");

  ImsListing out;
  fs::directory_iterator it(dir, ec);
  if (ec) throw InputError(dir, 0, "cannot list directory: " + ec.message());
  for (const fs::directory_entry& entry : it) {
    const std::string name = entry.path().filename().string();
    const std::optional<std::int64_t> t = parse_ims_timestamp(name);
    std::error_code fec;
    // is_regular_file() follows symlinks, so a link to a snapshot counts as a snapshot.
    if (t && entry.is_regular_file(fec)) {
      out.snapshots.push_back(ImsSnapshotInfo{entry.path().string(), name, *t, 0});
    } else {
      out.ignored.push_back(name);
    }
  }
  // Sort by time, then name so that "X" precedes "X.gz"; keep the first of equal times.
  std::sort(out.snapshots.begin(), out.snapshots.end(), [](const ImsSnapshotInfo& a, const ImsSnapshotInfo& b) {
    return a.time_ns != b.time_ns ? a.time_ns < b.time_ns : a.name < b.name;
  });
  std::vector<ImsSnapshotInfo> unique;
  unique.reserve(out.snapshots.size());
  for (ImsSnapshotInfo& s : out.snapshots) {
    if (!unique.empty() && unique.back().time_ns == s.time_ns) {
      out.ignored.push_back(s.name);
      continue;
    }
    s.index = unique.size();
    unique.push_back(std::move(s));
  }
  out.snapshots = std::move(unique);
  std::sort(out.ignored.begin(), out.ignored.end());
  if (out.snapshots.empty()) {
    throw InputError(dir, 0, "no IMS snapshot file (name YYYY.MM.DD.hh.mm.ss[.gz]) in directory");
  }
  return out;
}

}  // namespace causal::io
