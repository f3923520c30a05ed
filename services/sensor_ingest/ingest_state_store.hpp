// Restart safety of sensor-ingest (--state-dir DIR): per asset group, DIR/<asset group>.ingest.state holds the
// group's numbering (ResumePoint: next frame sequence, next sample index, last snapshot index, channels), written
// after every admitted block and BEFORE its frame is published. A restarted sensor-ingest continues each group's
// numbering instead of starting at 0 again: the estimator skips input whose indices it already processed (a
// resending replay), so a live source that numbered from 0 again would have its new data taken for old.
// Saving before publishing means a crash can leave a number unused (a gap the estimator counts as lost frames),
// never a number used twice. Files are replaced atomically (causal/estimation/state_archive.hpp), not fsync'ed.
#pragma once

#include "block_sequencer.hpp"

#include "causal/io/group_state_files.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace causal::ingest {

class IngestStateStore {
 public:
  // dir empty: no persistence. Otherwise the directory is created; throws std::invalid_argument when it cannot be.
  explicit IngestStateStore(std::string dir) : files_(std::move(dir), ".ingest.state") {}
  bool enabled() const { return files_.enabled(); }
  std::string path(const std::string& asset_group) const { return files_.path(asset_group); }
  // The group's saved numbering; nullopt when there is none. Throws std::runtime_error naming the file when one
  // exists but cannot be read (damaged, another group's): silently numbering from 0 again is what this prevents.
  std::optional<ResumePoint> load(const std::string& asset_group) const;
  // False (counted, reason in last_error()) when the file cannot be written.
  [[nodiscard]] bool save(const std::string& asset_group, const ResumePoint& point);
  std::uint64_t saves() const { return files_.saves(); }
  std::uint64_t failures() const { return files_.failures(); }
  const std::string& last_error() const { return files_.last_error(); }

 private:
  io::GroupStateFiles files_;  // DIR/<asset group>.ingest.state
};

}  // namespace causal::ingest
