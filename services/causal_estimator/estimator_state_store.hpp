// Crash and restart safety of causal-estimator (--state-dir DIR): one checkpoint per asset group,
// DIR/<asset group>.estimator.state, holding the whole AssetPipeline (filters, smoothers, calibration, learned
// structure and centre, condition windows, the last source indices fed) and the condition-level output the
// readers have not acknowledged yet (serialized DDS messages, unacked_output.hpp). Written after every completed
// snapshot (a frame with end_of_segment, or a ready-made condition vector) and at exit, BEFORE that snapshot's
// output is queued for DDS. At restart the pipeline is restored, the listed output is sent again (it may not have
// reached every reader; consumers drop what they already have by index), and input already processed (source
// index not after the last one fed) is skipped, so a source that resends is not processed twice.
//
// Files are written atomically (temporary file + rename): a kill -9 while saving leaves the previous one. Not
// fsync'ed: survives a process crash, not a power loss.
#pragma once

#include "causal/io/group_state_files.hpp"
#include "causal/pipeline/asset_pipeline.hpp"

#include <climits>
#include <cstdint>
#include <string>
#include <vector>

namespace causal::estimator {

class EstimatorStateStore {
 public:
  // dir empty: no persistence. Otherwise the directory is created; throws std::invalid_argument when it cannot be.
  explicit EstimatorStateStore(std::string dir) : files_(std::move(dir), ".estimator.state") {}
  bool enabled() const { return files_.enabled(); }
  std::string path(const std::string& asset_group) const { return files_.path(asset_group); }

  // Restores `pipeline` from the asset group's checkpoint. False when there is none (or no persistence).
  // Throws estimation::StateError naming the file when one exists but cannot be used (damaged, other parameters,
  // other channel count): silently starting over would re-learn the baseline on whatever data comes now.
  // `resend` receives the saved output messages (opaque byte strings, see save()).
  // `last_time_ns` receives the data time of the last input fed (INT64_MIN when the checkpoint predates it).
  bool restore(const std::string& asset_group, pipeline::AssetPipeline& pipeline, std::vector<std::string>& resend,
               std::int64_t* last_time_ns = nullptr) const;
  // Saves the pipeline and `resend` (serialized messages to send again after a restart); returns false (and
  // counts it) when the file cannot be written, with the reason in last_error().
  // `last_time_ns`: the data time of the last input fed (tells a resent input from new data under old numbers).
  [[nodiscard]] bool save(const std::string& asset_group, const pipeline::AssetPipeline& pipeline,
            const std::vector<std::string>& resend, std::int64_t last_time_ns = INT64_MIN);

  std::uint64_t saves() const { return files_.saves(); }
  std::uint64_t failures() const { return files_.failures(); }
  const std::string& last_error() const { return files_.last_error(); }

 private:
  io::GroupStateFiles files_;  // DIR/<asset group>.estimator.state
};

}  // namespace causal::estimator
