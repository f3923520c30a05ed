// causal-estimator: what it keeps per asset group (one DDS instance), grouped by the role that keeps it:
// admission (order, continuity, duplicates, losses), processing (the pipeline and its logs), publishing (the
// output counters and the checkpoint's resend list).
#pragma once

#include "causal/metrics/metrics_registry.hpp"
#include "causal/pipeline/asset_pipeline.hpp"
#include "causal_twin.h"
#include "unacked_output.hpp"

#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace causal::estimator {

struct GroupState {
  explicit GroupState(const pipeline::AssetPipelineParams& p) : pipeline(p) {}
  // The input's arrival (steady clock) and its source time, for the data-age metrics.
  void note_input(std::int64_t source_time_ns);

  // --- processing (estimator_processing.cpp)
  pipeline::AssetPipeline pipeline;
  std::vector<std::string> channel_names;
  std::string feature;  // feature name of the condition-level model
  std::uint64_t frames = 0, refused_frames = 0, conditions_in = 0, refused_conditions = 0;
  std::string refused;                // why this asset group's input is refused (unusable checkpoint, a fault)
  std::uint64_t refused_inputs = 0;   // input of a refused group
  // Data time of the last input fed (frames: the last row's time), checkpointed: an input whose index was fed
  // already but whose time is later is not a resend but new data under old numbers (a source that restarted
  // its numbering, e.g. a sensor-ingest without --state-dir): refused and counted, never silently skipped.
  std::int64_t last_time_ns = INT64_MIN;
  bool adjustments_logged = false, tuning_logged = false;
  bool startup_logged = false;  // its start-up done (noise calibrated, window replayed): logged once
  bool sample_structure_logged = false, condition_structure_logged = false;
  // Prometheus: time to process one input (filters, smoothers, output queued), per asset group.
  metrics::Histogram* frame_seconds = nullptr;
  metrics::Histogram* condition_seconds = nullptr;
  // Data age: when the group's last input arrived (steady clock, ns; read by the scrape through input_age)
  // and the source's time of that input (estimator_last_input_timestamp_seconds).
  std::shared_ptr<std::atomic<std::int64_t>> last_arrival_ns = std::make_shared<std::atomic<std::int64_t>>(0);
  metrics::CallbackHandle input_age;
  metrics::Gauge* input_time = nullptr;

  // --- admission (estimator_admission.cpp, input_continuity.cpp)
  std::optional<std::uint64_t> last_sequence;
  // Condition inputs that arrived ahead of the next expected index wait here (ordered) until the missing ones
  // arrive or the reorder hold passes: Fast DDS 2.9 was seen delivering a burst of inputs after later ones
  // (e.g. 73..103 after 104, in a loaded test run, with no sample rejected), and the filters need order.
  std::map<std::uint64_t, causal_twin::ConditionVector> reorder;
  std::chrono::steady_clock::time_point reorder_since;
  std::uint64_t reordered = 0;        // inputs that arrived ahead and were fed in order after waiting
  std::set<std::uint64_t> holes;      // condition snapshot indices skipped over (may still arrive, out of order)
  std::uint64_t late_conditions = 0;  // ... that did: too late to feed, counted as lost
  std::uint64_t skipped = 0;          // input already processed before a restart (source index), skipped
  std::uint64_t renumbered = 0;
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
  std::uint64_t lost_frames = 0, lost_snapshots = 0, lost_conditions = 0;
  std::size_t lost_alarms = 0;
  metrics::Counter* lost_metric = nullptr;

  // --- publishing (estimator_publishing.cpp, estimator_resend.cpp)
  std::uint64_t sample_msgs = 0, condition_msgs = 0;  // factor batches (one per kind and index)
  std::uint64_t sample_sets = 0, condition_sets = 0;  // output.factor_messages set: the messages holding them
  UnackedOutput unacked;  // condition-level output not yet acknowledged: the checkpoint's resend list
};

}  // namespace causal::estimator
