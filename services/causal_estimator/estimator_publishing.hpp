// causal-estimator, publishing: everything that leaves the process. The writers (condition vectors, factor batches
// at both levels, alarms), the outbound queue between the filters and the writers, the checkpoint with its list of
// unacknowledged condition-level output (sent again after a restart), data-quality and HEALTH alarms, the output
// watchdog and the hot standby (publishes nothing while a primary is alive, takes over when it is gone).
#pragma once

#include "causal/dds/health_watch.hpp"
#include "causal/dds/outbound_queue.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/pipeline/asset_pipeline.hpp"
#include "causal_twinPubSubTypes.h"
#include "data_quality_alarms.hpp"
#include "estimator_group.hpp"
#include "estimator_options.hpp"
#include "estimator_state_store.hpp"
#include "factor_writers.hpp"
#include "stage_trace.hpp"
#include "standby_buffer.hpp"
#include "unacked_output.hpp"

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace causal::estimator {

class EstimatorPublisher {
 public:
  // `stop`: the event loop's stop flag (a blocked push gives up when it is set); it outlives the publisher.
  EstimatorPublisher(dds::Participant& participant, const EstimatorOptions& options, int condition_fixed_lag,
                     const std::atomic<bool>& stop);

  // "" when every named reader matched both factor writers within `timeout`; else the first one missing.
  std::string wait_for_readers(const std::vector<dds::NamedReaders>& wanted, std::chrono::milliseconds timeout);

  // Queues one input's output (`out`: condition vectors, factor reports at both levels); at the end of a
  // snapshot, checkpoints first (state + the condition-level output not yet acknowledged). `trace`: the frame
  // being traced (its write is stamped), or null.
  void publish(const std::string& name, GroupState& a, const pipeline::PipelineOutput& out, bool end_of_snapshot,
               const std::shared_ptr<StageTrace::Frame>& trace);
  // The data-quality and operating-state alarms of `out`'s quality events (and, at the end of a snapshot, its
  // clears), logged and published.
  void publish_quality(const std::string& name, const GroupState& a, const pipeline::PipelineOutput& out,
                       std::uint64_t snapshot, std::int64_t time_ns, bool end_of_snapshot);
  // Loud refusal: the first refused input of a group raises its input_refused DATA QUALITY alarm and logs an
  // error; later ones are counted only (the summary states them, the exit code is 4).
  void report_refusal(const std::string& name, std::uint64_t snapshot, std::int64_t time_ns, const std::string& problem);
  // A HEALTH alarm about refused or lost input: logged and, unless standing by, published.
  void raise_input_alarm(const std::string& asset_group, const std::string& kind, causal_twin::Severity severity,
                         std::size_t serial, double score, double threshold, const std::string& reason);
  void publish_health_alarm(causal_twin::Alarm alarm);
  // HEALTH alarms of this tick: the output watchdog, this process's certificate, silent or lost inputs (`health`).
  void publish_health(dds::HealthWatch& health);

  // Checkpoints: restore one group (false: none); the listed output is sent again (resend_restored).
  bool restore(const std::string& name, GroupState& a);
  std::string checkpoint_path(const std::string& name) const { return store_.path(name); }
  // Saved at exit before the pipeline's flush: a restart continues the streams as they were, not flushed.
  void checkpoint_at_exit(const std::string& name, GroupState& a);

  // At the start of processing (after the wait for readers): a standby counts the primary's absence from here.
  void start();
  // Standby: follows the primary's progress and takes over when it has been gone for takeover_after_s.
  void watch_primary();
  bool standing_by() const { return standing_by_; }
  // Delivers what is queued and waits for the readers' acknowledgements (briefly after a stop).
  void finish(bool stopping);

  // For the exit summary.
  const EstimatorStateStore& store() const { return store_; }
  const dds::OutboundQueue& outbound() const { return outbound_; }
  std::uint64_t standby_unpublished() const { return standby_unpublished_; }
  std::uint64_t standby_discarded() const { return standby_.discarded(); }

 private:
  struct Item {
    const char* stream;
    dds::OutboundQueue::Class cls;
    dds::OutboundQueue::WriteFn write;
    std::function<bool()> try_write;  // sample level: written at once when nothing is queued (write_or_push)
    std::uint64_t index;              // the snapshot (or sample) index it refers to
  };
  // The factor batches of one level's reports, appended to `items`; `listed` adds one to the resend list.
  void factor_items(const std::string& name, GroupState& a, const std::vector<pipeline::FactorReport>& reports,
                    bool condition, const std::function<UnackedOutput::Flag(std::string)>& listed,
                    const std::shared_ptr<StageTrace::Frame>& trace, std::vector<Item>& items);
  // One item writing `msg` (a CausalFactorBatch or a CausalFactorSet) at its level; `traced`: the write of the
  // frame's filter factors, stamped.
  template <typename Msg>
  void factor_item(std::shared_ptr<Msg> msg, bool condition, std::uint64_t index, UnackedOutput::Flag flag,
                   const std::shared_ptr<StageTrace::Frame>& traced, std::vector<Item>& items);
  void send_items(const std::string& name, std::vector<Item>& items, const std::shared_ptr<StageTrace::Frame>& trace);
  void log_condition_report(const std::string& name, const GroupState& a, const pipeline::FactorReport& r) const;
  void log_condition_reports(const std::string& name, const GroupState& a,
                             const std::vector<pipeline::FactorReport>& reports, bool condition) const;
  void resend_restored(const std::string& name, GroupState& a, const std::vector<std::string>& resend);
  // One listed factor message ('B' batch or 'S' set) queued again; false when its bytes do not decode.
  template <typename PubSubType>
  bool resend_factors(GroupState& a, const std::string& bytes);
  // The write's result; a written message's flag is set (UnackedOutput: written, awaiting acknowledgement).
  static dds::WriteResult mark(dds::WriteResult result, const UnackedOutput::Flag& flag);
  // Forgets the listed output every reader acknowledged (asked without waiting), before a checkpoint; then, with
  // begin_snapshot, starts the list of the snapshot being published.
  void settle_unacked(GroupState& a, bool begin_snapshot = false);
  void checkpoint(const std::string& name, GroupState& a, const std::vector<std::string>& resend);
  void push_alarm(const char* stream, causal_twin::Alarm alarm);
  void watch_output();  // HEALTH alarm while a reader keeps the drain thread waiting (stuck_after_s)
  // A HEALTH alarm (once) when this process's own certificate expires within kCertificateWarningDays.
  void check_certificate_expiry();
  static constexpr double kCertificateWarningDays = 14.0;

  dds::Participant& participant_;
  const EstimatorOptions& options_;
  int condition_fixed_lag_;
  const std::atomic<bool>& stop_;
  // Factor batches (one per kind and index, all outcomes), one message each or one set per input: condition
  // level, and sample level on its own writer with a deeper ring (qos.xml causal_factors_sample_writer: the
  // high-rate stream, the writer blocks less).
  FactorWriters factors_;
  dds::TypedWriter<causal_twin::ConditionVectorPubSubType> conditions_out_;
  dds::TypedWriter<causal_twin::AlarmPubSubType> quality_alarms_;
  EstimatorStateStore store_;
  DataQualityAlarms quality_;
  bool certificate_alarmed_ = false;
  std::optional<causal_twin::Alarm> stuck_alarm_;  // raised while a reader does not acknowledge
  // Hot standby (options_.standby): the primary's published output, read until the takeover.
  std::unique_ptr<dds::TypedReader<causal_twin::ConditionVectorPubSubType>> primary_progress_;
  StandbyBuffer standby_{65536};
  bool standing_by_ = false;
  std::chrono::steady_clock::time_point primary_seen_;
  std::uint64_t standby_unpublished_ = 0;  // sample-level output not kept while standing by
  dds::OutboundQueue outbound_;  // last: its drain thread stops before the writers are destroyed
};

}  // namespace causal::estimator
