// One checkpoint file per asset group in a service's --state-dir: DIR/<asset group><suffix> (the id made a
// safe file name), written atomically with save_state_file (causal/estimation/state_archive.hpp), with the
// saves and the failed saves counted. What goes into a file is the owning store's business
// (EstimatorStateStore, IngestStateStore); this is the folder, the names and the counting they share.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace causal::estimation {
class StateWriter;
}  // namespace causal::estimation

namespace causal::io {

// The regular files in `dir` whose names end in `suffix` (and are longer than it), sorted by path: a stable order,
// so the same restart restores and republishes in the same order.
std::vector<std::string> files_with_suffix(const std::string& dir, const std::string& suffix);

class GroupStateFiles {
 public:
  // dir empty: no persistence. Otherwise the directory is created; throws std::invalid_argument
  // ("--state-dir 'DIR' cannot be created: ...") when it cannot be.
  GroupStateFiles(std::string dir, std::string suffix);
  bool enabled() const { return !dir_.empty(); }
  std::string path(const std::string& asset_group) const;

  // The group's payload; nullopt when there is no file (or no persistence). Throws estimation::StateError naming
  // the file when it is unreadable, truncated or corrupted.
  std::optional<std::string> load(const std::string& asset_group) const;
  // Writes what `fill` puts into a StateWriter as the group's file. False (counted in failures(), reason in
  // last_error()) when a estimation::StateError says it cannot be written; true without persistence.
  [[nodiscard]] bool save(const std::string& asset_group, const std::function<void(estimation::StateWriter&)>& fill);

  std::uint64_t saves() const { return saves_; }
  std::uint64_t failures() const { return failures_; }
  const std::string& last_error() const { return last_error_; }

 private:
  std::string dir_;
  std::string suffix_;
  std::uint64_t saves_ = 0, failures_ = 0;
  std::string last_error_;
};

}  // namespace causal::io
