// causal-estimator's DDS node: frames (and ready-made condition vectors) in; causal factors and condition
// vectors out. One AssetPipeline per asset group (DDS instance). A shard (--shards FILE --shard NAME, or
// --shard-index/--shard-count) subscribes to content-filtered frames and condition inputs: it receives only its
// own asset groups (dds/asset_group_filter.hpp), so N estimators divide the work.
#pragma once

#include "causal/metrics/metrics_registry.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/health_watch.hpp"
#include "causal/dds/outbound_queue.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/pipeline/asset_pipeline.hpp"
#include "causal_twinPubSubTypes.h"
#include "data_quality_alarms.hpp"
#include "estimator_state_store.hpp"
#include "group_quota.hpp"
#include "stage_trace.hpp"
#include "standby_buffer.hpp"
#include "unacked_output.hpp"

#include <atomic>
#include <chrono>
#include <climits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace causal::estimator {

struct EstimatorOptions {
  dds::CommonOptions dds;
  std::string params_file;
  // The asset groups this estimator owns (every group by default); its readers are filtered to them.
  dds::AssetGroupSelection groups;
  std::string shard_name;  // for logs: the --shard NAME, or "I/N" for a hash slice
  double idle_exit_s = 0.0;    // exit after this long without data, once data has arrived (0 = never)
  double max_runtime_s = 0.0;  // hard stop (0 = none)
  // Wait for readers of participants with these names ("alarm-recommender", or "causal-recorder:1") on the
  // factor topic before processing (input queues meanwhile in the reliable, transient-local readers).
  std::vector<std::string> wait_for;
  double wait_timeout_s = 30.0;
  std::size_t outbound_capacity = 65536;
  // After a restore from a checkpoint: how long input that does not continue the checkpoint is held (not fed,
  // not dropped) for the source to resend the continuation (sensor-ingest's backlog, sensor-replay's rewind).
  // The wait ends at once when the continuation arrives; when it does not, the held input is fed and the gap
  // counted as lost (input_lost).
  double resume_wait_s = 10.0;
  double stuck_after_s = 3.0;    // a write waiting this long on a reader raises a HEALTH alarm
  bool standby = false;          // hot standby: publish nothing while a primary estimator is alive (StandbyBuffer)
  double takeover_after_s = 6.0; // the primary's absence (> its 5 s lease) after which the standby takes over  // after a restore: how long to wait for the source to resend the continuation
  bool verbose = false;
  double health_deadline_s = 30.0;  // estimator.yaml health.deadline_s (HealthWatch)
  GroupQuotaLimits quota;  // --max-groups, --max-groups-per-writer (group_quota.hpp)
  std::string stage_trace;  // per-frame stage timestamps written here at exit (stage_trace.hpp); empty = off
  std::string state_dir;  // checkpoints (EstimatorStateStore); empty = none  // log every condition-level factor vector (off: progress only)  // messages queued for the DDS writers (see OutboundQueue)
};

// The role tag an estimator announces (DdsSettings::role_tag): "shard " + its asset-group filter expression
// ("shard " alone when it owns every group). Primary and standby of one shard announce the same tag.
inline std::string shard_role_tag(const dds::AssetGroupSelection& groups) { return "shard " + groups.expression(); }


class EstimatorNode {
 public:
  EstimatorNode(EstimatorOptions options, pipeline::AssetPipelineParams params);
  // Exit codes: 0 done, 3 the named readers never came, 4 data was lost or refused on the way (see the summary).
  int run();
  void stop() { loop_.stop(); }

 private:
  struct Asset {
    explicit Asset(const pipeline::AssetPipelineParams& p) : pipeline(p) {}
    pipeline::AssetPipeline pipeline;
    std::vector<std::string> channel_names;
    std::optional<std::uint64_t> last_sequence;
    std::uint64_t frames = 0, lost_frames = 0, refused_frames = 0, conditions_in = 0, refused_conditions = 0;
    bool adjustments_logged = false;
    // Condition inputs that arrived ahead of the next expected index wait here (ordered) until the missing ones
    // arrive or kReorderHold passes: Fast DDS 2.9 was seen delivering a burst of inputs after later ones
    // (e.g. 73..103 after 104, in a loaded test run, with no sample rejected), and the filters need order.
    std::map<std::uint64_t, causal_twin::ConditionVector> reorder;
    std::chrono::steady_clock::time_point reorder_since;
    std::uint64_t reordered = 0;        // inputs that arrived ahead and were fed in order after waiting
    std::set<std::uint64_t> holes;      // condition snapshot indices skipped over (may still arrive, out of order)
    std::uint64_t late_conditions = 0;  // ... that did: too late to feed, counted as lost
    std::uint64_t sample_msgs = 0, condition_msgs = 0;  // factor batches (one per kind and index)
    std::string feature;  // feature name of the condition-level model
    UnackedOutput unacked;  // condition-level output not yet acknowledged: the checkpoint's resend list
    bool tuning_logged = false;
    bool sample_structure_logged = false, condition_structure_logged = false;
    std::string refused;                // why this asset group's input is refused (unusable checkpoint, a fault)
    std::uint64_t skipped = 0;          // input already processed before a restart (source index), skipped
    // Data time of the last input fed (frames: the last row's time), checkpointed: an input whose index was fed
    // already but whose time is later is not a resend but new data under old numbers (a source that restarted
    // its numbering, e.g. a sensor-ingest without --state-dir): refused and counted, never silently skipped.
    std::int64_t last_time_ns = INT64_MIN;
    std::uint64_t renumbered = 0;
    std::uint64_t refused_inputs = 0;   // input of a refused group
    // After a restore from a checkpoint: input that does not continue where the checkpoint ends is held (up to
    // kHoldMax inputs) until the continuation arrives (then the held input is dropped: the source resends it
    // after the continuation) or resume_wait_s ends (then it is fed, and the gap counted as lost): a restarted
    // estimator may receive a few inputs of the live stream before its source has resent its backlog.
    bool awaiting_continuation = false;
    std::chrono::steady_clock::time_point continuation_deadline;
    std::uint64_t ahead_dropped = 0;
    std::vector<causal_twin::VibrationFrame> held_frames;
    std::vector<causal_twin::ConditionVector> held_conditions;
    // Input that never reached this estimator (source sequence numbers, snapshot indices), counted here:
    // frames missing between two sequence numbers, snapshots missing after a restart or skipped over.
    std::uint64_t lost_snapshots = 0, lost_conditions = 0;
    std::size_t lost_alarms = 0;
    metrics::Counter* lost_metric = nullptr;
    // Prometheus: time to process one input (filters, smoothers, output queued), per asset group.
    metrics::Histogram* frame_seconds = nullptr;
    metrics::Histogram* condition_seconds = nullptr;
    // Data age: when the group's last input arrived (steady clock, ns; read by the scrape through input_age)
    // and the source's time of that input (estimator_last_input_timestamp_seconds).
    std::shared_ptr<std::atomic<std::int64_t>> last_arrival_ns = std::make_shared<std::atomic<std::int64_t>>(0);
    metrics::CallbackHandle input_age;
    metrics::Gauge* input_time = nullptr;
    void note_input(std::int64_t source_time_ns);
  };

  using WriterGuid = eprosima::fastrtps::rtps::GUID_t;
  bool mine(const std::string& asset_group) const;
  // Authorisation per asset group (dds/group_partitions.hpp): false when the writer's partitions, checked by
  // Fast DDS against its signed grant, do not name the group (counted per topic, logged, HEALTH alarm per writer
  // and group, exit 4). `frame`: a vibration frame (else a condition input).
  bool entitled(const std::string& asset_group, const WriterGuid* writer, bool frame);
  // A HEALTH alarm (once) when this process's own certificate expires within kCertificateWarningDays.
  void check_certificate_expiry();
  static constexpr double kCertificateWarningDays = 14.0;
  bool certificate_alarmed_ = false;
  // Quota on new asset groups (group_quota.hpp): false when the input is refused (counted, logged, alarmed).
  bool admitted(const std::string& asset_group, const WriterGuid* writer);
  // A HEALTH alarm about refused input (quota, grant): logged and, unless standing by, published.
  void raise_input_alarm(const std::string& asset_group, const std::string& kind, causal_twin::Severity severity,
                         std::size_t serial, double score, double threshold, const std::string& reason);
  void publish_health_alarm(causal_twin::Alarm alarm);
  // An input whose indices were processed already: a resend (skipped, counted) or new data under old numbers
  // (refused: counted, logged, alarmed, exit 4). Never processed either way.
  void not_again(const std::string& name, Asset& a, std::uint64_t snapshot, std::int64_t time_ns,
                 const std::string& what);
  Asset& asset(const std::string& asset_group);
  // `writer`: the DDS writer it came from (the per-writer group quota); null for inputs released from the reorder
  // hold (their group is known).
  void on_frame(const causal_twin::VibrationFrame& frame, const WriterGuid* writer);
  void on_condition(const causal_twin::ConditionVector& in, const WriterGuid* writer = nullptr);
  // Feeds the held inputs of `a` that are next in order; with force_first, the lowest one even after a gap
  // (its wait is over: the indices before it are holes, counted as lost if they still come).
  void drain_reorder(Asset& a, bool force_first);
  void release_expired_reorders(bool all);
  bool releasing_ = false;  // on_condition called from drain_reorder: never held again
  // Queues the output in out_; at the end of a snapshot, checkpoints first (state + the condition-level output).
  void publish(const std::string& name, Asset& a, bool end_of_snapshot);
  void resend_restored(const std::string& name, Asset& a, const std::vector<std::string>& resend);
  // The write's result; a written message's flag is set (UnackedOutput: written, awaiting acknowledgement).
  static dds::WriteResult mark(dds::WriteResult result, const UnackedOutput::Flag& flag);
  // Forgets the listed output every reader acknowledged (asked without waiting), before a checkpoint; then, with
  // begin_snapshot, starts the list of the snapshot being published.
  void settle_unacked(Asset& a, bool begin_snapshot = false);
  void publish_quality(const std::string& name, Asset& a, std::uint64_t snapshot, std::int64_t time_ns,
                       bool end_of_snapshot);
  void checkpoint(const std::string& name, Asset& a, const std::vector<std::string>& resend);
  // Standby: follows the primary's progress and takes over when it has been gone for takeover_after_s.
  void watch_primary();
  // False when the input is ahead of a restored checkpoint and the continuation is still awaited (it is held).
  bool continues(const std::string& name, Asset& a, bool is_continuation, const causal_twin::VibrationFrame* frame,
                 const causal_twin::ConditionVector* condition);
  // Ends the wait for the continuation: the held input is fed in order (the gap before it counted as lost).
  void release_held(const std::string& name, Asset& a);
  void release_expired_holds(bool all);
  // Counts input that never arrived (count, in `unit`: "frames" or "snapshots"), logs it and raises the group's
  // HEALTH alarm input_lost naming the missing range of snapshot indices [first, last].
  void report_input_lost(const std::string& name, Asset& a, std::uint64_t count, const char* unit,
                         std::uint64_t first, std::uint64_t last, const std::string& detail);
  // Loud refusal: the first refused input of a group raises its input_refused DATA QUALITY alarm and logs an
  // error; later ones are counted only (the summary states them, the exit code is 4).
  void report_refusal(const std::string& name, std::uint64_t snapshot, std::int64_t time_ns, const std::string& problem);
  void log_adjustments(const std::string& name, Asset& a);  // once per group, after its first accepted input
  void publish_health();
  void watch_output();      // HEALTH alarm while a reader keeps the drain thread waiting (stuck_after_s)    // HEALTH alarms of silent or lost inputs (HealthWatch), raised and cleared
  void log_structure(const std::string& name, const Asset& a, const char* level,
                     const pipeline::LearnedStructure* learned, bool& logged) const;
  void log_condition_report(const std::string& name, const Asset& a, const pipeline::FactorReport& r);
  int finish_all();  // publishes what is left, drains, logs the summary; returns the exit code
  int log_summary() const;  // the summary of finish_all; returns the exit code (4: something lost or refused)
  void report_rejections();  // logs samples the readers' resource limits refused

  EstimatorOptions options_;
  pipeline::AssetPipelineParams params_;
  dds::Participant participant_;
  dds::TypedReader<causal_twin::VibrationFramePubSubType> frames_;
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> conditions_in_;
  // Factor batches (one per kind and index, all outcomes): condition level, and sample level on its own writer
  // with a deeper ring (qos.xml causal_factors_sample_writer: the high-rate stream, the writer blocks less).
  dds::TypedWriter<causal_twin::CausalFactorBatchPubSubType> factors_;
  dds::TypedWriter<causal_twin::CausalFactorBatchPubSubType> sample_factors_;
  dds::TypedWriter<causal_twin::ConditionVectorPubSubType> conditions_out_;
  dds::TypedWriter<causal_twin::AlarmPubSubType> quality_alarms_;
  dds::EventLoop loop_;  // after the readers: detaches their conditions first
  std::map<std::string, Asset> assets_;
  pipeline::PipelineOutput out_;
  causal_twin::ConditionVector condition_msg_;
  EstimatorStateStore store_;
  // Hot standby (options_.standby): the primary's published output, read until the takeover.
  std::unique_ptr<dds::TypedReader<causal_twin::ConditionVectorPubSubType>> primary_progress_;
  StandbyBuffer standby_{65536};
  bool standing_by_ = false;
  std::chrono::steady_clock::time_point primary_seen_;
  std::uint64_t standby_unpublished_ = 0;
  std::optional<causal_twin::Alarm> stuck_alarm_;  // raised while a reader does not acknowledge  // sample-level output not kept while standing by
  DataQualityAlarms quality_;
  dds::HealthWatch health_;
  std::uint64_t foreign_frames_ = 0, invalid_msgs_ = 0;
  GroupQuota quota_;
  std::set<std::string> quota_alarmed_writers_;  // one HEALTH alarm per writer over its quota
  std::uint64_t not_entitled_frames_ = 0, not_entitled_conditions_ = 0;  // refused by entitled()
  dds::WriterGrantCheck grants_;  // per-group grants of the input writers; one HEALTH alarm per writer and group
  metrics::Counter* not_processed_entitlement_ = nullptr;
  metrics::Counter* not_processed_renumbered_ = nullptr;  // estimator_inputs_not_processed_total{reason=..}
  metrics::Counter* not_processed_quota_ = nullptr;
  metrics::Counter* not_processed_invalid_ = nullptr;
  metrics::Counter* not_processed_already_ = nullptr;
  std::uint64_t rejected_no_instance_ = 0, rejected_no_room_ = 0;  // refused by our readers' resource limits
  StageTrace trace_;
  std::shared_ptr<StageTrace::Frame> frame_trace_;  // the frame being processed, when tracing
  dds::OutboundQueue outbound_;  // last: its drain thread stops before the writers are destroyed
};

}  // namespace causal::estimator
