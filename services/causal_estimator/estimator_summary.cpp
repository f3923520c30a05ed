// causal-estimator, the exit summary: one line per asset group, then machine-readable lines (launch.sh,
// deploy/bench_scale.sh and the tests read them), gathered from the three roles.
#include "estimator_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/sample_limits.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

// The summary: one line per asset group, then machine-readable lines (launch.sh and the tests read them).
int EstimatorNode::log_summary() const {
  const EstimatorAdmission::Counts& inputs = admission_.counts();
  std::uint64_t frames = 0, lost = 0, refused = 0, conditions_received = 0, conditions_refused = 0, conditions_late = 0;
  for (const auto& [name, a] : processing_.groups()) {
    const auto* s = a.pipeline.sample_stream();
    spdlog::info("asset '{}': {} frames ({} lost, {} refused), {} snapshots lost after a restart, {} condition vectors "
                 "in ({} lost), {} sample-level and {} condition-level factor messages out, {} non-finite rejected",
                 name, a.frames, a.lost_frames, a.refused_frames, a.lost_snapshots, a.conditions_in + a.refused_conditions,
                 a.lost_conditions,
                 a.sample_msgs, a.condition_msgs,
                 s ? s->counters().rejected_non_finite : 0);
    if (options_.factor_sets) {
      spdlog::info("asset '{}': those factor batches went in {} sample-level and {} condition-level factor-set messages "
                   "(output.factor_messages set: one per input)", name, a.sample_sets, a.condition_sets);
    }
    if (a.skipped > 0) spdlog::info("asset '{}': {} inputs processed before a restart skipped", name, a.skipped);
    if (a.renumbered > 0) {
      spdlog::error("asset '{}': {} inputs refused: numbered as processed already but later in time (a source that "
                    "restarted its numbering)", name, a.renumbered);
    }
    if (!a.refused.empty()) {
      spdlog::error("asset '{}': {} inputs refused: {}", name, a.refused_inputs, a.refused);
    }
    frames += a.frames;
    lost += a.lost_frames + a.lost_snapshots;
    refused += a.refused_frames + a.refused_inputs + a.renumbered;
    conditions_received += a.conditions_in;
    conditions_refused += a.refused_conditions;
    conditions_late += a.lost_conditions;
    if (a.reordered > 0) {
      spdlog::info("asset '{}': {} condition vectors arrived ahead of earlier ones and were fed in order", name,
                   a.reordered);
    }
    if (a.late_conditions > 0) spdlog::error("asset '{}': {} condition vectors came after later ones (lost)", name, a.late_conditions);
  }
  if (publisher_.store().enabled()) {
    spdlog::info("{} checkpoints written to '{}', {} failed", publisher_.store().saves(), options_.state_dir, publisher_.store().failures());
  }
  if (inputs.foreign > 0) {
    spdlog::info("{} frames/condition inputs of other shards received and ignored (the content filter let them "
                 "through: their asset group could not be read)", inputs.foreign);
  }
  if (inputs.invalid > 0) spdlog::warn("{} malformed messages refused", inputs.invalid);
  if (admission_.quota().refused_inputs() > 0) {
    spdlog::error("{} inputs of {} asset groups refused by the quota (--max-groups {}, --max-groups-per-writer {})",
                  admission_.quota().refused_inputs(), admission_.quota().refused_groups(), admission_.quota().limits().max_groups,
                  admission_.quota().limits().max_groups_per_writer);
  }
  std::uint64_t skipped = 0, renumbered = 0;
  for (const auto& [name, a] : processing_.groups()) {
    skipped += a.skipped;
    renumbered += a.renumbered;
  }
  // Machine-readable: every input received and not processed, by reason (the tests read it).
  const std::uint64_t not_entitled = inputs.not_entitled_frames + inputs.not_entitled_conditions;
  if (not_entitled > 0) {
    spdlog::error("{} inputs refused: their writers may not write their asset group ({} writer/group pairs)",
                  not_entitled, admission_.refused_grant_pairs());
  }
  const std::uint64_t dds_refused = dds::refusals_total();  // refused by the readers (sample_limits.hpp)
  spdlog::info("summary not_processed already_processed={} renumbered={} group_quota={} invalid={} not_entitled={} "
               "groups={} dds_refused={}",
               skipped, renumbered, admission_.quota().refused_inputs(), inputs.invalid, not_entitled, processing_.groups().size(), dds_refused);
  if (!options_.groups.all()) {
    // Machine-readable: the fault test checks that shards divide the groups exactly.
    spdlog::info("summary shard={} groups={} foreign={} filter='{}'", options_.shard_name, processing_.groups().size(),
                 inputs.foreign, options_.groups.expression());
  }
  std::uint64_t published = 0, unpublished = 0;
  const auto streams = publisher_.outbound().counters();
  for (const auto& [stream, c] : streams) {
    if (stream.rfind("causal_factors", 0) == 0) published += c.written;
    unpublished += c.dropped + c.failed;
  }
  spdlog::info("causal-estimator: received frames={} groups={} lost={} refused={} rejected_instances={} "
               "rejected_no_room={} published factors={} unpublished={}",
               frames, processing_.groups().size(), lost, refused + inputs.invalid + dds_refused, inputs.rejected_no_instance, inputs.rejected_no_room, published,
               unpublished);
  spdlog::info("summary topic=causal_twin/vibration_frame received={} lost={} refused={} not_entitled={}",
               frames + refused + inputs.not_entitled_frames, lost,
               refused + inputs.invalid + inputs.rejected_no_instance + inputs.not_entitled_frames, inputs.not_entitled_frames);
  spdlog::info("summary topic=causal_twin/condition_input received={} refused={} lost={} not_entitled={}",
               conditions_received + conditions_refused + conditions_late + inputs.not_entitled_conditions,
               conditions_refused + inputs.not_entitled_conditions, conditions_late, inputs.not_entitled_conditions);
  // Snapshots whose condition window was dropped (too few usable samples: a channel quarantined for the whole
  // snapshot, a gap): stated here and in the data-quality alarms, never published as a vector.
  std::uint64_t dropped_windows = 0;
  for (const auto& [name, a] : processing_.groups()) {
    if (a.pipeline.dropped_condition_windows() > 0) {
      spdlog::warn("asset '{}': {} snapshots without a condition vector (too few usable samples in the window)", name,
                   a.pipeline.dropped_condition_windows());
    }
    dropped_windows += a.pipeline.dropped_condition_windows();
  }
  spdlog::info("summary topic=causal_twin/condition_vector windows_dropped={}", dropped_windows);
  for (const auto& [stream, c] : streams) {
    spdlog::info("summary topic=causal_twin/{} sent={} dropped={} failed={}", stream, c.written, c.dropped, c.failed);
  }
  // Machine-readable: the process's CPU over the run (deploy/bench_scale.sh compares it with the kernel).
  spdlog::info("summary cpu {}", process_cpu_summary(frames));
  if (trace_.enabled()) {
    const std::string problem = trace_.write();
    if (problem.empty()) spdlog::info("stage trace: {} frames written to '{}'", trace_.rows(), options_.stage_trace);
    else spdlog::error("stage trace: {}", problem);
  }
  const auto& h = admission_.health().health();
  spdlog::info("summary health sources={} raised={} cleared={} active={} deadline_s={}", h.sources(), h.raised(),
               h.cleared(), h.active_alarms(), h.deadline_s());
  spdlog::info("outbound queue high-water mark: {} of {} messages", publisher_.outbound().high_water(), options_.outbound_capacity);
  if (options_.standby) {
    spdlog::info("hot standby: {}; {} sample-level messages not kept while standing by, {} retained messages "
                 "pushed out by newer ones", publisher_.standing_by() ? "never took over (the primary stayed)" : "took over",
                 publisher_.standby_unpublished(), publisher_.standby_discarded());
  }
  return (lost + refused + conditions_refused + conditions_late + inputs.invalid + inputs.rejected_no_instance + unpublished +
          dropped_windows + admission_.quota().refused_inputs() + not_entitled + dds_refused) > 0
             ? config::kExitLostOrRefused : config::kExitOk;
}

}  // namespace causal::estimator
