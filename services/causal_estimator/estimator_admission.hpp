// causal-estimator, admission: the readers (frames and condition inputs, content-filtered to this shard's asset
// groups) and the screen every input passes before processing: shard, well-formedness, the writer's grant, the
// quota on new groups, inputs processed already (a resend, or new data under old numbers), order (condition
// inputs that arrive ahead wait, bounded) and continuity (after a restore, input ahead of the checkpoint waits for
// the source's resend; input that never came is counted as lost). Nothing is dropped silently: every input not
// processed is counted (summary, estimator_inputs_not_processed_total{reason}), refusals are logged, alarmed and
// make the exit code 4.
#pragma once

#include "causal/dds/event_loop.hpp"
#include "causal/dds/health_watch.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal/metrics/metrics_registry.hpp"
#include "causal_twinPubSubTypes.h"
#include "estimator_group.hpp"
#include "estimator_options.hpp"
#include "estimator_processing.hpp"
#include "estimator_publishing.hpp"
#include "group_quota.hpp"
#include "stage_trace.hpp"

#include <atomic>
#include <cstdint>
#include <memory>
#include <set>
#include <string>

namespace causal::estimator {

class EstimatorAdmission {
 public:
  // The readers are created here; `processing` and `publisher` are used from the first take() on.
  EstimatorAdmission(dds::Participant& participant, const EstimatorOptions& options, EstimatorProcessing& processing,
                     EstimatorPublisher& publisher, StageTrace& trace);
  void attach(dds::EventLoop& loop);

  // Takes every input waiting in the readers and hands what passes the screen to processing; returns how many
  // samples were taken (instance state changes included).
  std::size_t take(const std::atomic<bool>& stop);
  // Every tick: condition inputs held for order and input held for a continuation whose wait is over go in; the
  // readers' refusals are reported.
  void tick();
  // At the end of the run: the sources have finished, so everything held goes in (in order).
  void finish();

  std::size_t matched_writers() const { return frames_.matched_writers() + conditions_in_.matched_writers(); }
  std::size_t matched_writers_total() const {
    return frames_.matched_writers_total() + conditions_in_.matched_writers_total();
  }
  dds::HealthWatch& health() { return health_; }
  const dds::HealthWatch& health() const { return health_; }

  // For the exit summary: inputs not processed, by reason.
  struct Counts {
    std::uint64_t foreign = 0, invalid = 0;                              // other shards' input, malformed
    std::uint64_t not_entitled_frames = 0, not_entitled_conditions = 0;  // refused by the writers' grants
    std::uint64_t rejected_no_instance = 0, rejected_no_room = 0;        // refused by our readers' resource limits
  };
  const Counts& counts() const { return counts_; }
  const GroupQuota& quota() const { return quota_; }
  std::size_t refused_grant_pairs() const { return grants_.refused_pairs(); }

 private:
  using WriterGuid = eprosima::fastrtps::rtps::GUID_t;
  // `writer`: the DDS writer it came from (the grant, the per-writer group quota); null for inputs released from
  // a hold (checked when they arrived).
  void on_frame(const causal_twin::VibrationFrame& frame, const WriterGuid* writer);
  void on_condition(const causal_twin::ConditionVector& in, const WriterGuid* writer = nullptr);
  // The screen both kinds of input pass: shard, form (`problem`: the validation's verdict), grant, quota, a
  // refused group. Null when the input stops here (counted); else its group, the input noted.
  GroupState* screen(const std::string& group, const std::string& problem, const WriterGuid* writer, bool frame,
                     std::uint64_t number, std::uint64_t snapshot, std::int64_t time_ns);
  // True when frames were lost before this one (sequence numbers, or samples after a restart): counted, alarmed.
  bool frame_gap(const causal_twin::VibrationFrame& frame, GroupState& a);
  // Authorisation per asset group (dds/group_partitions.hpp): false when the writer's partitions, checked by
  // Fast DDS against its signed grant, do not name the group (counted per topic, logged, HEALTH alarm per writer
  // and group, exit 4). `frame`: a vibration frame (else a condition input).
  bool entitled(const std::string& asset_group, const WriterGuid* writer, bool frame);
  // Quota on new asset groups (group_quota.hpp): false when the input is refused (counted, logged, alarmed).
  bool admitted(const std::string& asset_group, const WriterGuid* writer);
  // An input whose indices were processed already: a resend (skipped, counted) or new data under old numbers
  // (refused: counted, logged, alarmed, exit 4). Never processed either way.
  void not_again(const std::string& name, GroupState& a, std::uint64_t snapshot, std::int64_t time_ns,
                 const std::string& what);
  // Feeds the held inputs of `a` that are next in order; with force_first, the lowest one even after a gap
  // (its wait is over: the indices before it are holes, counted as lost if they still come).
  void drain_reorder(GroupState& a, bool force_first);
  void release_expired_reorders(bool all);
  // False when the input is ahead of a restored checkpoint and the continuation is still awaited (it is held).
  bool continues(const std::string& name, GroupState& a, bool is_continuation,
                 const causal_twin::VibrationFrame* frame, const causal_twin::ConditionVector* condition);
  // Ends the wait for the continuation: the held input is fed in order (the gap before it counted as lost).
  void release_held(const std::string& name, GroupState& a);
  void release_expired_holds(bool all);
  // Counts input that never arrived (count, in `unit`: "frames" or "snapshots"), logs it and raises the group's
  // HEALTH alarm input_lost naming the missing range of snapshot indices [first, last].
  void report_input_lost(const std::string& name, GroupState& a, std::uint64_t count, const char* unit,
                         std::uint64_t first, std::uint64_t last, const std::string& detail);
  void report_rejections();  // logs samples the readers' resource limits refused

  const EstimatorOptions& options_;
  EstimatorProcessing& processing_;
  EstimatorPublisher& publisher_;
  StageTrace& trace_;
  dds::TypedReader<causal_twin::VibrationFramePubSubType> frames_;
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> conditions_in_;
  dds::HealthWatch health_;
  GroupQuota quota_;
  std::set<std::string> quota_alarmed_writers_;  // one HEALTH alarm per writer over its quota
  dds::WriterGrantCheck grants_;  // per-group grants of the input writers; one HEALTH alarm per writer and group
  Counts counts_;
  metrics::Counter* not_processed_entitlement_ = nullptr;  // estimator_inputs_not_processed_total{reason=..}
  metrics::Counter* not_processed_renumbered_ = nullptr;
  metrics::Counter* not_processed_quota_ = nullptr;
  metrics::Counter* not_processed_invalid_ = nullptr;
  metrics::Counter* not_processed_already_ = nullptr;
  bool releasing_ = false;  // on_condition called from drain_reorder or release_held: never held again
  std::shared_ptr<StageTrace::Frame> frame_trace_;  // the frame being processed, when tracing
};

}  // namespace causal::estimator
