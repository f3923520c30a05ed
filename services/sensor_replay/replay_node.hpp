// sensor-replay's DDS node: entities are built in the constructor, run() publishes the whole source with
// pacing, stop() (from the signal thread) ends it early. Exit codes: 0 done, 1 bad input, 3 no readers.
#pragma once

#include "replay_options.hpp"
#include "snapshot_source.hpp"

#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace causal::replay {

class ReplayNode {
 public:
  explicit ReplayNode(ReplayOptions options);
  int run();
  void stop();

 private:
  int run_raw(const SnapshotSource& source);
  int run_features();
  // Throws io::InputError naming the first channel name outside the name limit.
  void check_names(const std::vector<std::string>& channel_names) const;
  // Sleeps until plant time `plant_ns` is due at the configured speed. False if stopped meanwhile.
  bool pace(std::int64_t plant_ns);
  void report_progress(std::size_t done, std::size_t total, bool force);
  // True when the readers asked for are matched (waiting, bounded, when they are not); false on stop/timeout.
  template <typename Writer>
  bool readers_present(const Writer& writer, bool first);
  // Restart safety: when a new reader of a named participant appears after publishing began (an estimator
  // that restarted), the snapshot to resume from: the one after the last snapshot the estimators published
  // for this asset group (causal_twin/condition_vector), so nothing it received but had not processed is lost.
  // The estimator skips what its checkpoint already holds. nullopt: carry on.
  template <typename Writer>
  std::optional<std::size_t> rewind_point(const Writer& writer, std::size_t first, std::size_t next);

  ReplayOptions options_;
  dds::Participant participant_;
  std::unique_ptr<dds::TypedWriter<causal_twin::VibrationFramePubSubType>> frames_;
  std::unique_ptr<dds::TypedWriter<causal_twin::ConditionVectorPubSubType>> conditions_;
  std::vector<dds::NamedReaders> wanted_;
  std::unique_ptr<dds::TypedReader<causal_twin::ConditionVectorPubSubType>> progress_;  // the estimators' output
  std::set<eprosima::fastrtps::rtps::GUID_t> known_readers_;
  bool readers_known_ = false;
  std::optional<std::uint64_t> published_;  // highest snapshot index the estimators published for this group
  std::uint64_t rewinds_ = 0;
  bool readers_missing_ = false;  // set when a wait timed out (exit 3)
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::chrono::steady_clock::time_point wall_origin_;
  std::int64_t plant_origin_ns_ = 0;
  bool origin_set_ = false;
  std::chrono::steady_clock::time_point last_progress_;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace causal::replay
