// sensor-ingest's DDS node: a source (MQTT, UDP, stdin) fills a bounded queue; next() takes each message,
// parses it (ingest_block.hpp), orders it into the asset group's frame stream (block_sequencer.hpp) and hands it
// to the one source driver (causal/dds/source_driver.hpp) as a VibrationFrame; a ready-made feature row
// (feature_row.hpp) goes out as a ConditionVector on causal_twin/condition_input. Bad messages are rejected and
// counted by reason, never fatal. A restarted estimator gets the kept frames after its last snapshot again.
// Exit codes: 0 done, 3 no readers in time, 4 a message was rejected or a frame lost.
#pragma once

#include <Eigen/Core>

#include <array>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "block_sequencer.hpp"
#include "feature_row.hpp"
#include "frame_backlog.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/sample_source.hpp"
#include "causal/dds/source_driver.hpp"
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

class IngestNode final : public dds::SampleSource {
 public:
  explicit IngestNode(IngestOptions options);
  ~IngestNode() override;
  int run() { return driver_.run(*this); }
  void stop();

  void start(dds::SourceDriver& driver) override;
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  void written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame* built) override;
  std::uint64_t refused() const override;
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  // One message into `out`; false when it was rejected (counted).
  bool process(const std::string& message, dds::SourceBlock& out);
  // A ready-made feature row (feature_row.hpp) onto causal_twin/condition_input: same rejections and counts.
  bool process_features(const std::string& message, dds::SourceBlock& out);
  void count_rejection(RejectReason reason, const std::string& detail, const std::string& group);
  // For an estimator that appeared since the last look (a restart): every kept frame after the last snapshot
  // an estimator published for its group, queued to go out before the next message.
  void resend(const dds::PublishedSnapshots& published);
  void resend_group(const std::string& group, const dds::PublishedSnapshots& published);

  IngestOptions options_;
  dds::Participant participant_;
  dds::SourceDriver driver_;
  const dds::SourceDriver* running_ = nullptr;
  MessageQueue queue_;
  std::unique_ptr<MessageSource> source_;
  BlockSequencer sequencer_;
  IngestStateStore numbering_;  // --state-dir: numbering continued across restarts
  // Loads a group's saved numbering before its first block (false: the state file is unusable; counted).
  bool resume_numbering(const std::string& group);
  std::uint64_t resumed_groups_ = 0;
  RateLimitedLog numbering_log_;
  Eigen::MatrixXd block_;  // the samples of the frame handed out last
  struct FeatureStream {
    std::uint64_t last_sequence = 0;
    std::int64_t last_time_ns = 0;
    std::vector<std::string> channels;
    std::string feature;
  };
  std::map<std::string, FeatureStream> feature_streams_;
  std::uint64_t features_published_ = 0;
  FrameBacklog backlog_;
  std::vector<std::string> reader_names_;  // whose new readers get the backlog
  std::deque<const causal_twin::VibrationFrame*> pending_;  // kept frames to resend, before the held message
  std::optional<std::string> held_;
  bool holding_ = false;
  std::uint64_t resends_ = 0, beyond_backlog_ = 0;

  std::uint64_t received_ = 0, published_ = 0, non_finite_ = 0, discontinuities_ = 0;
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
