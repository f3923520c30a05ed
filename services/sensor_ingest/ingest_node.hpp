// sensor-ingest's DDS node: a source (MQTT, UDP, stdin) fills a bounded queue; run() takes each message,
// parses it (ingest_block.hpp), orders it into the asset group's frame stream (block_sequencer.hpp) and
// publishes it as a VibrationFrame; a ready-made feature row (feature_row.hpp) goes out as a ConditionVector on
// causal_twin/condition_input. Bad messages are rejected and counted by reason, never fatal.
// Exit codes: 0 done, 3 no readers in time, 4 a message was rejected or a frame lost.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "block_sequencer.hpp"
#include "feature_row.hpp"
#include "frame_backlog.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/metrics/metrics_registry.hpp"
#include "causal_twinPubSubTypes.h"
#include "ingest_options.hpp"
#include "ingest_sources.hpp"
#include "ingest_state_store.hpp"

namespace causal::ingest {

// Logs the first few events of a class at once, then at most one line per interval with the count since.
class RateLimitedLog {
 public:
  // True when this event should be logged now; `suppressed` is set to the events skipped since the last line.
  bool allow(std::uint64_t& suppressed);

 private:
  std::uint64_t seen_ = 0, skipped_ = 0;
  std::chrono::steady_clock::time_point last_{};
};

class IngestNode {
 public:
  explicit IngestNode(IngestOptions options);
  ~IngestNode();
  int run();
  void stop();

 private:
  using Clock = std::chrono::steady_clock;
  void process(const std::string& message);
  // A ready-made feature row (feature_row.hpp) onto causal_twin/condition_input: same rejections and counts.
  void process_features(const std::string& message);
  void count_rejection(RejectReason reason, const std::string& detail, const std::string& group);
  void print_summary() const;
  // Resends the backlog to an estimator that appeared since the last look (a restart): every kept frame after
  // the last snapshot an estimator published for its group (read from causal_twin/condition_vector).
  void resend_to_new_readers();
  void resend_group(const std::string& group);

  IngestOptions options_;
  dds::Participant participant_;
  dds::TypedWriter<causal_twin::VibrationFramePubSubType> frames_;
  MessageQueue queue_;
  std::unique_ptr<MessageSource> source_;
  BlockSequencer sequencer_;
  IngestStateStore numbering_;  // --state-dir: numbering continued across restarts
  // Loads a group's saved numbering before its first block (false: the state file is unusable; counted).
  bool resume_numbering(const std::string& group);
  std::uint64_t resumed_groups_ = 0;
  RateLimitedLog numbering_log_;
  causal_twin::VibrationFrame frame_;
  dds::TypedWriter<causal_twin::ConditionVectorPubSubType> features_;
  causal_twin::ConditionVector feature_msg_;
  struct FeatureStream {
    std::uint64_t last_sequence = 0;
    std::int64_t last_time_ns = 0;
    std::vector<std::string> channels;
    std::string feature;
  };
  std::map<std::string, FeatureStream> feature_streams_;
  std::uint64_t features_published_ = 0;
  bool features_ready_ = false;  // the condition-input readers were waited for (before the first feature row)
  FrameBacklog backlog_;
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> progress_;  // the estimators' published snapshots
  std::map<std::string, std::uint64_t> estimator_published_;  // last snapshot an estimator published, per group
  std::set<eprosima::fastrtps::rtps::GUID_t> known_readers_, new_readers_;
  std::vector<std::string> reader_names_;  // whose new readers get the backlog
  Clock::time_point last_look_{};
  std::uint64_t resent_ = 0, resends_ = 0, beyond_backlog_ = 0;
  std::atomic<bool> stop_{false};
  Clock::time_point deadline_ = Clock::time_point::max();

  std::uint64_t received_ = 0, published_ = 0, lost_ = 0, non_finite_ = 0, discontinuities_ = 0;
  std::uint64_t missed_ = 0;  // source blocks lost across a restart (FramePlan::missed)
  std::array<std::uint64_t, kRejectReasonCount> rejected_{};
  std::array<RateLimitedLog, kRejectReasonCount> reject_log_{};
  RateLimitedLog discontinuity_log_, non_finite_log_;
  metrics::Counter* received_metric_;
  metrics::Counter* published_metric_;
  metrics::Counter* lost_metric_;
  metrics::Counter* non_finite_metric_;
  metrics::Counter* discontinuity_metric_;
  metrics::Counter* missed_metric_;
  std::array<metrics::Counter*, kRejectReasonCount> rejected_metric_{};
};

}  // namespace causal::ingest
