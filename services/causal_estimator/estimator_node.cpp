// causal-estimator, input side: the run loop, frames and condition inputs per asset group (validation, duplicates,
// order, continuation after a restart) fed into the pipelines. The output side is estimator_output.cpp.
#include "estimator_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <cstring>
#include <stdexcept>

namespace causal::estimator {

namespace {
// The participant announces its shard (the asset-group filter expression, "" unsharded): a hot standby follows
// only the primary of its own shard, so another shard's estimator is never taken for its primary.
dds::DdsSettings estimator_dds_settings(const EstimatorOptions& options) {
  auto settings = dds::to_dds_settings(options.dds, "causal-estimator");
  settings.role_tag = shard_role_tag(options.groups);
  return settings;
}
// How long condition inputs that arrived ahead wait for the ones before them, and how many may wait.
constexpr std::chrono::milliseconds kReorderHold{2000};
constexpr std::size_t kReorderMax = 4096;
}  // namespace

EstimatorNode::EstimatorNode(EstimatorOptions options, pipeline::AssetPipelineParams params)
    : options_(std::move(options)),
      params_(std::move(params)),
      participant_(estimator_dds_settings(options_)),
      // Filtered to this shard's asset groups: the sources' writers drop the other shards' samples.
      frames_(participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameReader, options_.groups),
      conditions_in_(participant_, dds::topics::kConditionInput, dds::profiles::kConditionInputReader, options_.groups),
      factors_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsWriter),
      sample_factors_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsSampleWriter),
      conditions_out_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorWriter),
      quality_alarms_(participant_, dds::topics::kAlarm, dds::profiles::kAlarmWriter),
      store_(options_.state_dir),
      health_(options_.health_deadline_s, "frames/condition inputs", "source",
              {dds::topics::kVibrationFrame, dds::topics::kConditionInput}),
      quota_(options_.quota),
      grants_(participant_.directory(), "input", "input", "issue-identity.sh --groups"),
      trace_(options_.stage_trace),
      outbound_(options_.outbound_capacity) {
  loop_.attach(frames_.get());
  loop_.attach(conditions_in_.get());
  // Sample-level noise tuning (~18 ms per group at 4096 samples) runs on one worker thread: a group that is
  // still tuning buffers its frames and no other group's frames wait behind it. Same reports, later.
  if (params_.sample.noise.automatic) params_.sample.noise.worker = std::make_shared<pipeline::TuningWorker>();
  const char* help = "Inputs (frames, condition inputs) the estimator received but did not process, by reason";
  auto& m = metrics::process_metrics();
  not_processed_already_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "already_processed"}});
  not_processed_renumbered_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "renumbered"}});
  not_processed_quota_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "group_quota"}});
  not_processed_invalid_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "invalid"}});
  not_processed_entitlement_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "not_entitled"}});
  if (options_.standby) {
    standing_by_ = true;
    primary_progress_ = std::make_unique<dds::TypedReader<causal_twin::ConditionVectorPubSubType>>(
        participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader);
  }
}

void EstimatorNode::watch_primary() {
  if (!standing_by_) return;
  const auto own = conditions_out_.get()->guid();
  primary_progress_->take_all([&](const causal_twin::ConditionVector& c, const auto& info) {
    if (info.sample_identity.writer_guid() != own) standby_.primary_published(c.asset_group(), c.snapshot_index());
  });
  const auto now = std::chrono::steady_clock::now();
  if (participant_.directory().writers_named(dds::topics::kConditionVector, "causal-estimator",
                                             shard_role_tag(options_.groups)) > 0) {
    primary_seen_ = now;
    return;
  }
  if (std::chrono::duration<double>(now - primary_seen_).count() < options_.takeover_after_s) return;
  // The primary is gone: publish what it may not have, then go on as the primary.
  standing_by_ = false;
  primary_progress_.reset();  // never read our own output
  // From before the primary's last condition vector by the smoother's lag (its fixed-lag reports trail) + 2.
  const auto margin = static_cast<std::uint64_t>(std::max(0, params_.condition_model.fixed_lag)) + 2;
  auto items = standby_.take_over(margin);
  spdlog::warn("no primary causal-estimator for {:.0f} s: taking over; {} retained messages published again from {} "
               "snapshots before the primary's last one (readers drop what they have)",
               options_.takeover_after_s, items.size(), margin);
  for (auto& item : items) outbound_.push(item.stream, item.cls, std::move(item.write), loop_.stop_flag());
}

// The content filter already keeps other shards' samples away; this check catches what a filter could not
// judge (a sample whose asset group it could not read is let through) and is counted (foreign_frames_).
void EstimatorNode::Asset::note_input(std::int64_t source_time_ns) {
  last_arrival_ns->store(std::chrono::nanoseconds(std::chrono::steady_clock::now().time_since_epoch()).count(),
                         std::memory_order_relaxed);
  if (input_time != nullptr) input_time->set(static_cast<double>(source_time_ns) * 1e-9);
}

bool EstimatorNode::mine(const std::string& asset_group) const { return options_.groups.matches(asset_group); }

EstimatorNode::Asset& EstimatorNode::asset(const std::string& asset_group) {
  auto it = assets_.find(asset_group);
  if (it == assets_.end()) {
    it = assets_.emplace(asset_group, Asset(params_)).first;
    Asset& a = it->second;
    const char* help = "Time to process one input of an asset group (filters, smoothers, output queued)";
    a.frame_seconds = &metrics::process_metrics().histogram("estimator_processing_seconds", help,
                                                            {{"asset_group", asset_group}, {"input", "frame"}},
                                                            metrics::latency_buckets_seconds());
    a.condition_seconds = &metrics::process_metrics().histogram("estimator_processing_seconds", help,
                                                                {{"asset_group", asset_group}, {"input", "condition"}},
                                                                metrics::latency_buckets_seconds());
    a.input_age = metrics::process_metrics().gauge_callback(
        "estimator_input_age_seconds", "Seconds since the asset group's last input (frame or condition vector) arrived",
        {{"asset_group", asset_group}}, [t = a.last_arrival_ns] {
          const std::int64_t last = t->load(std::memory_order_relaxed);
          const auto now = std::chrono::steady_clock::now().time_since_epoch();
          return last == 0 ? 0.0 : static_cast<double>(std::chrono::nanoseconds(now).count() - last) * 1e-9;
        });
    a.input_time = &metrics::process_metrics().gauge(
        "estimator_last_input_timestamp_seconds",
        "Source time (UTC, Unix seconds) of the asset group's last input: time() minus this is the data's age",
        {{"asset_group", asset_group}});
    try {
      std::vector<std::string> resend;
      if (store_.restore(asset_group, a.pipeline, resend, &a.last_time_ns)) {
        // The names come with the checkpoint: output (finish() at exit included) needs them before any new input.
        a.channel_names = a.pipeline.channel_names();
        resend_restored(asset_group, a, resend);
        a.awaiting_continuation = true;
        a.continuation_deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(
                                                                          static_cast<long>(options_.resume_wait_s * 1000));
        const auto& last = a.pipeline.last_source_index();
        spdlog::info("asset group '{}' resumed from checkpoint {}: last snapshot {}, last sample {}", asset_group,
                     store_.path(asset_group), last.has_snapshot ? std::to_string(last.snapshot) : "none",
                     last.has_sample ? std::to_string(last.sample) : "none");
      } else {
        spdlog::info("new asset group '{}'", asset_group);
      }
    } catch (const std::exception& e) {
      // Only this asset group stops: the others carry on (bad input is isolated).
      a.refused = e.what();
      spdlog::error("asset group '{}': {}; its input is refused (counted) until this is fixed", asset_group, e.what());
    }
  }
  return it->second;
}

int EstimatorNode::run() {
  if (options_.groups.all()) {
    spdlog::info("causal-estimator on domain {}, every asset group, waiting for frames", participant_.domain_id());
  } else {
    spdlog::info("causal-estimator on domain {}, shard {}: {} (content filter '{}' on frames and condition inputs, "
                 "evaluated by the sources' writers), waiting for frames",
                 participant_.domain_id(), options_.shard_name, options_.groups.describe(), options_.groups.expression());
  }
  if (!options_.wait_for.empty()) {
    // Input that arrives meanwhile waits in the reliable, transient-local readers: nothing is lost.
    std::vector<dds::NamedReaders> wanted;
    for (const auto& spec : options_.wait_for) wanted.push_back(dds::parse_named_readers(spec));
    const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.wait_timeout_s * 1000.0));
    std::string missing = dds::wait_for_named_readers(factors_, wanted, timeout, loop_.stop_flag());
    if (missing.empty()) missing = dds::wait_for_named_readers(sample_factors_, wanted, timeout, loop_.stop_flag());
    if (!missing.empty()) {
      if (loop_.stopped()) return config::kExitOk;
      spdlog::error("no '{}' reader of causal factors matched within {:.0f} s: is it running on domain {} with the "
                    "same transport profile?",
                    missing, options_.wait_timeout_s, participant_.domain_id());
      return config::kExitNoPeer;
    }
  }
  dds::RunLimits limits;
  limits.idle_exit_s = options_.idle_exit_s;
  limits.max_runtime_s = options_.max_runtime_s;
  // A shard may own none of the groups a source publishes and then receives nothing at all: for it, sources
  // that came and left are the end of the run (otherwise it would never be idle, and never exit).
  if (!options_.groups.all()) {
    limits.sources_came = [this] { return frames_.matched_writers_total() + conditions_in_.matched_writers_total() > 0; };
  }
  primary_seen_ = std::chrono::steady_clock::now();
  if (standing_by_) spdlog::info("hot standby: publishing nothing while a primary causal-estimator is alive");
  const auto end = loop_.run(
      limits,
      [this] {
        watch_primary();
        // Samples without data are instance state changes: a source that ended (disposed) or was lost.
        const auto state = [this](const auto& info) {
          spdlog::debug("input instance state change: {}", static_cast<int>(info.instance_state));
          health_.on_state(info);
        };
        const std::size_t n =
            frames_.take_all_and_states(
                [this](const auto& f, const auto& info) {
                  if (mine(f.asset_group())) health_.on_sample(f.asset_group(), f.snapshot_index(), info);
                  const WriterGuid writer = info.sample_identity.writer_guid();
                  if (trace_.enabled()) {
                    frame_trace_ = std::make_shared<StageTrace::Frame>();
                    frame_trace_->group = f.asset_group();
                    frame_trace_->sequence = f.sequence_number();
                    frame_trace_->due_ns = f.first_sample_time_ns();
                    frame_trace_->source_ns = info.source_timestamp.to_ns();
                    frame_trace_->received_ns = info.reception_timestamp.to_ns();
                    frame_trace_->taken_ns = StageTrace::now_ns();
                  }
                  on_frame(f, &writer);
                  if (frame_trace_) trace_.keep(std::move(frame_trace_));
                },
                state, loop_.stop_flag()) +
            conditions_in_.take_all_and_states(
                [this](const auto& c, const auto& info) {
                  if (mine(c.asset_group())) health_.on_sample(c.asset_group(), c.snapshot_index(), info);
                  const WriterGuid writer = info.sample_identity.writer_guid();
                  on_condition(c, &writer);
                },
                state, loop_.stop_flag());
        release_expired_reorders(false);
        release_expired_holds(false);
        report_rejections();
        publish_health();
        return n;
      },
      // Idle exit only once every source has left: a source that is merely blocked or paced must not end the run.
      [this] { return frames_.matched_writers() + conditions_in_.matched_writers(); });
  if (end == dds::RunEnd::Idle) spdlog::info("all sources gone and no data for {:.1f} s: finishing", options_.idle_exit_s);
  if (end == dds::RunEnd::MaxRuntime) spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
  return finish_all();
}

void EstimatorNode::on_frame(const causal_twin::VibrationFrame& frame, const WriterGuid* writer) {
  if (!mine(frame.asset_group())) {
    ++foreign_frames_;
    return;
  }
  if (const std::string problem = dds::validate_frame(frame); !problem.empty()) {
    ++invalid_msgs_;
    not_processed_invalid_->inc();
    spdlog::warn("asset '{}': frame {} refused: {}", frame.asset_group(), frame.sequence_number(), problem);
    return;
  }
  if (!entitled(frame.asset_group(), writer, true) || !admitted(frame.asset_group(), writer)) return;
  Asset& a = asset(frame.asset_group());
  a.note_input(frame.first_sample_time_ns());
  if (!a.refused.empty()) {
    ++a.refused_inputs;
    report_refusal(frame.asset_group(), frame.snapshot_index(), frame.first_sample_time_ns(), a.refused);
    return;
  }
  if (a.pipeline.already_fed_frame(frame.first_sample_index(), frame.samples_per_channel())) {
    not_again(frame.asset_group(), a, frame.snapshot_index(), frame.first_sample_time_ns(),
              fmt::format("frame {} (samples {}..)", frame.sequence_number(), frame.first_sample_index()));
    a.last_sequence = frame.sequence_number();
    return;
  }
  {
    const auto& last = a.pipeline.last_source_index();
    if (!continues(frame.asset_group(), a, !last.has_sample || frame.first_sample_index() == last.sample + 1, &frame,
                   nullptr)) {
      return;
    }
  }
  // Sequence numbers run 0, 1, 2, ... per publisher; a jump means frames were lost on the way, a return to
  // 0 a restarted publisher (its first frame is flagged as a discontinuity anyway).
  bool gap = false;
  const auto& last = a.pipeline.last_source_index();
  if (a.last_sequence && frame.sequence_number() != *a.last_sequence + 1 && frame.sequence_number() != 0) {
    gap = true;
    if (frame.sequence_number() > *a.last_sequence) {
      report_input_lost(frame.asset_group(), a, frame.sequence_number() - *a.last_sequence - 1, "frames",
                        last.has_snapshot ? last.snapshot : frame.snapshot_index(), frame.snapshot_index(),
                        fmt::format("frames {}..{} missing; lags restart", *a.last_sequence + 1,
                                    frame.sequence_number() - 1));
    }
  } else if (!a.last_sequence && last.has_sample && frame.first_sample_index() > last.sample + 1) {
    // After a restart (no sequence number yet): samples between the checkpoint and this frame never came.
    gap = true;
    const std::uint64_t first = last.has_snapshot ? last.snapshot + 1 : frame.snapshot_index();
    const std::uint64_t missing = frame.snapshot_index() > first ? frame.snapshot_index() - first : 1;
    report_input_lost(frame.asset_group(), a, missing, "snapshots", first,
                      frame.snapshot_index() > first ? frame.snapshot_index() - 1 : frame.snapshot_index(),
                      fmt::format("samples {}..{} missing after the restart", last.sample + 1,
                                  frame.first_sample_index() - 1));
  }
  a.last_sequence = frame.sequence_number();
  if (a.channel_names.empty()) {
    a.channel_names = dds::channel_names(frame);
    a.pipeline.set_channel_names(a.channel_names);
  }
  out_.clear();
  const auto started = std::chrono::steady_clock::now();
  // Indices come from the source, so reports keep them across a restart or a lost frame.
  pipeline::FrameCheck check;
  try {
    check = a.pipeline.feed_frame(dds::samples_view(frame), frame.first_sample_index(), frame.snapshot_index(),
                                  frame.discontinuity(), frame.end_of_segment(), gap, frame.first_sample_time_ns(),
                                  frame.sample_rate_hz(), out_);
  } catch (const std::exception& e) {
    // A fault in one asset group's estimation must not end the others: this group stops, loudly.
    a.refused = std::string("estimation failed: ") + e.what();
    spdlog::error("asset '{}': {}; its input is refused from now on (counted)", frame.asset_group(), a.refused);
    ++a.refused_inputs;
    report_refusal(frame.asset_group(), frame.snapshot_index(), frame.first_sample_time_ns(), a.refused);
    return;
  }
  if (frame_trace_) frame_trace_->fed_ns = StageTrace::now_ns();
  if (!check.ok) {
    ++a.refused_frames;
    spdlog::debug("asset '{}': frame {} refused: {}", frame.asset_group(), frame.sequence_number(), check.problem);
    report_refusal(frame.asset_group(), frame.snapshot_index(), frame.first_sample_time_ns(), check.problem);
    return;
  }
  log_adjustments(frame.asset_group(), a);
  ++a.frames;
  a.last_time_ns = frame.first_sample_time_ns() +
                   static_cast<std::int64_t>(static_cast<double>(std::max<std::uint32_t>(frame.samples_per_channel(), 1) - 1) *
                                             1e9 / frame.sample_rate_hz());
  if (a.feature.empty()) a.feature = io::to_string(params_.condition.feature);
  publish_quality(frame.asset_group(), a, frame.snapshot_index(), frame.first_sample_time_ns(), frame.end_of_segment());
  publish(frame.asset_group(), a, frame.end_of_segment());
  a.frame_seconds->observe(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

void EstimatorNode::on_condition(const causal_twin::ConditionVector& in, const WriterGuid* writer) {
  if (!mine(in.asset_group())) {
    ++foreign_frames_;
    return;
  }
  if (const std::string problem = dds::validate_condition_vector(in); !problem.empty()) {
    ++invalid_msgs_;
    not_processed_invalid_->inc();
    spdlog::warn("asset '{}': condition vector {} refused: {}", in.asset_group(), in.snapshot_index(), problem);
    return;
  }
  if (!entitled(in.asset_group(), writer, false) || !admitted(in.asset_group(), writer)) return;
  Asset& a = asset(in.asset_group());
  a.note_input(in.time_ns());
  if (!a.refused.empty()) {
    ++a.refused_inputs;
    report_refusal(in.asset_group(), in.snapshot_index(), in.time_ns(), a.refused);
    return;
  }
  if (a.pipeline.already_fed_condition(in.snapshot_index())) {
    if (a.holes.erase(in.snapshot_index()) > 0) {
      // Never fed, and later ones were: it arrived out of order (seen with a reader history full under load),
      // too late for the filters. A loss, stated loudly, not a duplicate.
      ++a.late_conditions;
      spdlog::error("asset '{}': condition vector {} arrived after later ones (out of order): too late to be fed, "
                    "counted as lost",
                    in.asset_group(), in.snapshot_index());
      return;
    }
    not_again(in.asset_group(), a, in.snapshot_index(), in.time_ns(),
              fmt::format("condition vector {}", in.snapshot_index()));
    return;
  }
  if (!releasing_) {
    const auto& last = a.pipeline.last_source_index();
    if (last.has_snapshot && !a.awaiting_continuation && in.snapshot_index() > last.snapshot + 1 &&
        a.reorder.size() < kReorderMax) {
      // Ahead of the next expected index: wait (bounded) for the ones before it, then feed in order.
      if (a.reorder.empty()) a.reorder_since = std::chrono::steady_clock::now();
      a.reorder.emplace(in.snapshot_index(), in);
      return;
    }
  }
  {
    const auto& last = a.pipeline.last_source_index();
    if (last.has_snapshot && !a.awaiting_continuation && in.snapshot_index() > last.snapshot + 1) {
      // Indices skipped over: the source may not have them, or they may still come (out of order, too late to
      // be fed): lost either way, counted now.
      for (std::uint64_t i = last.snapshot + 1; i < in.snapshot_index() && a.holes.size() < 65536; ++i) a.holes.insert(i);
      report_input_lost(in.asset_group(), a, in.snapshot_index() - last.snapshot - 1, "condition inputs", last.snapshot + 1,
                        in.snapshot_index() - 1, "condition inputs skipped over");
    }
  }
  {
    const auto& last = a.pipeline.last_source_index();
    if (!continues(in.asset_group(), a, !last.has_snapshot || in.snapshot_index() == last.snapshot + 1, nullptr, &in)) {
      return;
    }
  }
  if (a.channel_names.empty()) {
    a.channel_names.assign(in.channel_names().begin(), in.channel_names().end());
    a.pipeline.set_channel_names(a.channel_names);
  }
  if (a.feature.empty()) a.feature = in.feature();
  out_.clear();
  const auto started = std::chrono::steady_clock::now();
  pipeline::FrameCheck check;
  try {
    check = a.pipeline.feed_condition(dds::values_of(in), in.snapshot_index(), in.discontinuity(), in.time_ns(), out_);
  } catch (const std::exception& e) {
    a.refused = std::string("estimation failed: ") + e.what();
    spdlog::error("asset '{}': {}; its input is refused from now on (counted)", in.asset_group(), a.refused);
    ++a.refused_inputs;
    report_refusal(in.asset_group(), in.snapshot_index(), in.time_ns(), a.refused);
    return;
  }
  if (!check.ok) {
    ++a.refused_conditions;
    spdlog::debug("asset '{}': condition vector {} refused: {}", in.asset_group(), in.snapshot_index(), check.problem);
    report_refusal(in.asset_group(), in.snapshot_index(), in.time_ns(), check.problem);
    return;
  }
  log_adjustments(in.asset_group(), a);
  ++a.conditions_in;
  a.last_time_ns = in.time_ns();
  // The accepted vector goes on to the estimator's own topic: the one stream of condition vectors that the
  // recommender, the recorder and the HMI read, whatever the source.
  pipeline::ConditionSample accepted;
  accepted.snapshot_index = in.snapshot_index();
  accepted.time_ns = in.time_ns();
  accepted.values = dds::values_of(in);
  accepted.discontinuity = in.discontinuity();
  out_.conditions.insert(out_.conditions.begin(), std::move(accepted));
  publish_quality(in.asset_group(), a, in.snapshot_index(), in.time_ns(), true);
  publish(in.asset_group(), a, true);
  a.condition_seconds->observe(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  if (!releasing_ && !a.reorder.empty()) drain_reorder(a, false);
}

void EstimatorNode::drain_reorder(Asset& a, bool force_first) {
  bool force = force_first;
  while (!a.reorder.empty()) {
    auto it = a.reorder.begin();
    const auto& last = a.pipeline.last_source_index();
    const bool next = !last.has_snapshot || it->first <= last.snapshot + 1;
    if (!next && !force) break;
    force = false;
    const causal_twin::ConditionVector msg = std::move(it->second);
    a.reorder.erase(it);
    if (next) ++a.reordered;
    releasing_ = true;
    on_condition(msg, nullptr);
    releasing_ = false;
    a.reorder_since = std::chrono::steady_clock::now();  // the rest waits afresh for its own predecessors
  }
}

void EstimatorNode::release_expired_reorders(bool all) {
  const auto now = std::chrono::steady_clock::now();
  for (auto& [name, a] : assets_) {
    if (a.reorder.empty()) continue;
    if (all) {
      while (!a.reorder.empty()) drain_reorder(a, true);
    } else if (now - a.reorder_since >= kReorderHold) {
      spdlog::warn("asset '{}': condition vectors before {} did not arrive within {} ms: going on without them "
                   "(counted as lost if they come later)", name, a.reorder.begin()->first,
                   std::chrono::duration_cast<std::chrono::milliseconds>(kReorderHold).count());
      drain_reorder(a, true);
    }
  }
}



}  // namespace causal::estimator
