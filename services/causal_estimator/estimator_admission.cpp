// causal-estimator, admission: the readers and the screen of every input (shard, form, grant, quota, duplicates,
// order) before it reaches processing. Continuity after a restore and the count of lost input are
// input_continuity.cpp.
#include "estimator_admission.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <sstream>

namespace causal::estimator {

namespace {
// How long condition inputs that arrived ahead wait for the ones before them, and how many may wait.
constexpr std::chrono::milliseconds kReorderHold{2000};
constexpr std::size_t kReorderMax = 4096;
}  // namespace

EstimatorAdmission::EstimatorAdmission(dds::Participant& participant, const EstimatorOptions& options,
                                       EstimatorProcessing& processing, EstimatorPublisher& publisher,
                                       StageTrace& trace)
    : options_(options),
      processing_(processing),
      publisher_(publisher),
      trace_(trace),
      // Filtered to this shard's asset groups: the sources' writers drop the other shards' samples.
      frames_(participant, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameReader, options_.groups),
      conditions_in_(participant, dds::topics::kConditionInput, dds::profiles::kConditionInputReader, options_.groups),
      health_(options_.health_deadline_s, "frames/condition inputs", "source",
              {dds::topics::kVibrationFrame, dds::topics::kConditionInput}),
      quota_(options_.quota),
      grants_(participant.directory(), "input", "input", "issue-identity.sh --groups") {
  const char* help = "Inputs (frames, condition inputs) the estimator received but did not process, by reason";
  auto& m = metrics::process_metrics();
  not_processed_already_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "already_processed"}});
  not_processed_renumbered_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "renumbered"}});
  not_processed_quota_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "group_quota"}});
  not_processed_invalid_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "invalid"}});
  not_processed_entitlement_ = &m.counter("estimator_inputs_not_processed_total", help, {{"reason", "not_entitled"}});
}

void EstimatorAdmission::attach(dds::EventLoop& loop) {
  loop.attach(frames_.get());
  loop.attach(conditions_in_.get());
}

std::size_t EstimatorAdmission::take(const std::atomic<bool>& stop) {
  // Samples without data are instance state changes: a source that ended (disposed) or was lost.
  const auto state = [this](const auto& info) {
    spdlog::debug("input instance state change: {}", static_cast<int>(info.instance_state));
    health_.on_state(info);
  };
  const auto frame = [this](const auto& f, const auto& info) {
    if (options_.groups.matches(f.asset_group())) health_.on_sample(f.asset_group(), f.snapshot_index(), info);
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
  };
  const auto condition = [this](const auto& c, const auto& info) {
    if (options_.groups.matches(c.asset_group())) health_.on_sample(c.asset_group(), c.snapshot_index(), info);
    const WriterGuid writer = info.sample_identity.writer_guid();
    on_condition(c, &writer);
  };
  return frames_.take_all_and_states(frame, state, stop) + conditions_in_.take_all_and_states(condition, state, stop);
}

void EstimatorAdmission::tick() {
  release_expired_reorders(false);
  release_expired_holds(false);
  report_rejections();
}

void EstimatorAdmission::finish() {
  release_expired_holds(true);     // the source has finished: no continuation will come now
  release_expired_reorders(true);  // the source has finished: what is held goes in, in order
  report_rejections();
}

GroupState* EstimatorAdmission::screen(const std::string& group, const std::string& problem, const WriterGuid* writer,
                                       bool frame, std::uint64_t number, std::uint64_t snapshot, std::int64_t time_ns) {
  // The content filter already keeps other shards' samples away; this check catches what a filter could not
  // judge (a sample whose asset group it could not read is let through) and is counted.
  if (!options_.groups.matches(group)) {
    ++counts_.foreign;
    return nullptr;
  }
  if (!problem.empty()) {
    ++counts_.invalid;
    not_processed_invalid_->inc();
    spdlog::warn("asset '{}': {} {} refused: {}", group, frame ? "frame" : "condition vector", number, problem);
    return nullptr;
  }
  if (!entitled(group, writer, frame) || !admitted(group, writer)) return nullptr;
  GroupState& a = processing_.group(group);
  a.note_input(time_ns);
  if (!a.refused.empty()) {
    ++a.refused_inputs;
    publisher_.report_refusal(group, snapshot, time_ns, a.refused);
    return nullptr;
  }
  return &a;
}

void EstimatorAdmission::on_frame(const causal_twin::VibrationFrame& frame, const WriterGuid* writer) {
  const std::string& name = frame.asset_group();
  GroupState* group = screen(name, dds::validate_frame(frame), writer, true, frame.sequence_number(),
                             frame.snapshot_index(), frame.first_sample_time_ns());
  if (group == nullptr) return;
  GroupState& a = *group;
  if (a.pipeline.already_fed_frame(frame.first_sample_index(), frame.samples_per_channel())) {
    not_again(name, a, frame.snapshot_index(), frame.first_sample_time_ns(),
              fmt::format("frame {} (samples {}..)", frame.sequence_number(), frame.first_sample_index()));
    a.last_sequence = frame.sequence_number();
    return;
  }
  {
    const auto& last = a.pipeline.last_source_index();
    if (!continues(name, a, !last.has_sample || frame.first_sample_index() == last.sample + 1, &frame, nullptr)) return;
  }
  const bool gap = frame_gap(frame, a);
  a.last_sequence = frame.sequence_number();
  processing_.feed_frame(frame, a, gap, frame_trace_);
}

bool EstimatorAdmission::frame_gap(const causal_twin::VibrationFrame& frame, GroupState& a) {
  // Sequence numbers run 0, 1, 2, ... per publisher; a jump means frames were lost on the way, a return to
  // 0 a restarted publisher (its first frame is flagged as a discontinuity anyway).
  const std::string& name = frame.asset_group();
  const auto& last = a.pipeline.last_source_index();
  if (a.last_sequence && frame.sequence_number() != *a.last_sequence + 1 && frame.sequence_number() != 0) {
    if (frame.sequence_number() > *a.last_sequence) {
      report_input_lost(name, a, frame.sequence_number() - *a.last_sequence - 1, "frames",
                        last.has_snapshot ? last.snapshot : frame.snapshot_index(), frame.snapshot_index(),
                        fmt::format("frames {}..{} missing; lags restart", *a.last_sequence + 1,
                                    frame.sequence_number() - 1));
    }
    return true;
  }
  if (!a.last_sequence && last.has_sample && frame.first_sample_index() > last.sample + 1) {
    // After a restart (no sequence number yet): samples between the checkpoint and this frame never came.
    const std::uint64_t first = last.has_snapshot ? last.snapshot + 1 : frame.snapshot_index();
    const std::uint64_t missing = frame.snapshot_index() > first ? frame.snapshot_index() - first : 1;
    report_input_lost(name, a, missing, "snapshots", first,
                      frame.snapshot_index() > first ? frame.snapshot_index() - 1 : frame.snapshot_index(),
                      fmt::format("samples {}..{} missing after the restart", last.sample + 1,
                                  frame.first_sample_index() - 1));
    return true;
  }
  return false;
}

void EstimatorAdmission::on_condition(const causal_twin::ConditionVector& in, const WriterGuid* writer) {
  const std::string& name = in.asset_group();
  GroupState* group = screen(name, dds::validate_condition_vector(in), writer, false, in.snapshot_index(),
                             in.snapshot_index(), in.time_ns());
  if (group == nullptr) return;
  GroupState& a = *group;
  if (a.pipeline.already_fed_condition(in.snapshot_index())) {
    if (a.holes.erase(in.snapshot_index()) > 0) {
      // Never fed, and later ones were: it arrived out of order (seen with a reader history full under load),
      // too late for the filters. A loss, stated loudly, not a duplicate.
      ++a.late_conditions;
      spdlog::error("asset '{}': condition vector {} arrived after later ones (out of order): too late to be fed, "
                    "counted as lost",
                    name, in.snapshot_index());
      return;
    }
    not_again(name, a, in.snapshot_index(), in.time_ns(), fmt::format("condition vector {}", in.snapshot_index()));
    return;
  }
  const auto& last = a.pipeline.last_source_index();
  const bool ahead = last.has_snapshot && !a.awaiting_continuation && in.snapshot_index() > last.snapshot + 1;
  if (ahead && !releasing_ && a.reorder.size() < kReorderMax) {
    // Ahead of the next expected index: wait (bounded) for the ones before it, then feed in order.
    if (a.reorder.empty()) a.reorder_since = std::chrono::steady_clock::now();
    a.reorder.emplace(in.snapshot_index(), in);
    return;
  }
  if (ahead) {
    // Indices skipped over: the source may not have them, or they may still come (out of order, too late to
    // be fed): lost either way, counted now.
    for (std::uint64_t i = last.snapshot + 1; i < in.snapshot_index() && a.holes.size() < 65536; ++i) a.holes.insert(i);
    report_input_lost(name, a, in.snapshot_index() - last.snapshot - 1, "condition inputs", last.snapshot + 1,
                      in.snapshot_index() - 1, "condition inputs skipped over");
  }
  if (!continues(name, a, !last.has_snapshot || in.snapshot_index() == last.snapshot + 1, nullptr, &in)) return;
  processing_.feed_condition(in, a);
  if (!releasing_ && !a.reorder.empty()) drain_reorder(a, false);
}

void EstimatorAdmission::drain_reorder(GroupState& a, bool force_first) {
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

void EstimatorAdmission::release_expired_reorders(bool all) {
  const auto now = std::chrono::steady_clock::now();
  for (auto& [name, a] : processing_.groups()) {
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

bool EstimatorAdmission::entitled(const std::string& asset_group, const WriterGuid* writer, bool frame) {
  if (writer == nullptr) return true;  // released from the reorder hold: checked when it arrived
  if (grants_.entitled(asset_group, *writer)) return true;
  (frame ? counts_.not_entitled_frames : counts_.not_entitled_conditions) += 1;
  not_processed_entitlement_->inc();
  for (auto& alarm : grants_.take_alarms()) publisher_.publish_health_alarm(std::move(alarm));
  return false;
}

bool EstimatorAdmission::admitted(const std::string& asset_group, const WriterGuid* writer) {
  std::string who;
  if (writer != nullptr) {
    std::ostringstream text;
    text << *writer;
    who = text.str();
  }
  const auto verdict = quota_.admit(asset_group, who);
  if (verdict == GroupQuota::Verdict::Known || verdict == GroupQuota::Verdict::Admitted) return true;
  not_processed_quota_->inc();
  const auto& limits = quota_.limits();
  const std::string why =
      verdict == GroupQuota::Verdict::OverTotal
          ? fmt::format("this estimator already serves {} asset groups (--max-groups {})", quota_.groups(),
                        limits.max_groups)
          : fmt::format("writer {} already opened {} asset groups (--max-groups-per-writer {})", who,
                        quota_.groups_of(who), limits.max_groups_per_writer);
  if (!quota_alarmed_writers_.insert(who).second) return false;  // counted; one alarm and error line per writer
  spdlog::error("asset group '{}' refused: {}; its input and further new groups of this writer are refused "
                "(counted, exit 4)", asset_group, why);
  publisher_.raise_input_alarm(asset_group, "asset_group_quota", causal_twin::WARNING, quota_alarmed_writers_.size(),
                               static_cast<double>(quota_.groups()),
                               static_cast<double>(verdict == GroupQuota::Verdict::OverTotal
                                                       ? limits.max_groups
                                                       : limits.max_groups_per_writer),
                               "new asset group '" + asset_group + "' refused: " + why +
                                   "; a source that names ever new groups would exhaust memory and checkpoint files");
  return false;
}

void EstimatorAdmission::not_again(const std::string& name, GroupState& a, std::uint64_t snapshot,
                                   std::int64_t time_ns, const std::string& what) {
  // A resend (a restarted replay, the transient-local history) carries its old times; new data is later than
  // the last input fed. Without a known last time (a checkpoint from before it was kept) it counts as a resend.
  if (a.last_time_ns == INT64_MIN || time_ns <= a.last_time_ns) {
    ++a.skipped;
    not_processed_already_->inc();
    return;
  }
  ++a.renumbered;
  not_processed_renumbered_->inc();
  const std::string problem =
      fmt::format("the source's numbering went back: {} of snapshot {} was processed already, but its data time {} is "
                  "after the last input processed ({}): a source that restarted its numbering (sensor-ingest keeps it "
                  "with --state-dir); such input is refused, not taken for a resend",
                  what, snapshot, io::format_utc(time_ns), io::format_utc(a.last_time_ns));
  if (a.renumbered == 1) spdlog::error("asset '{}': {}", name, problem);
  publisher_.report_refusal(name, snapshot, time_ns, problem);
}

void EstimatorAdmission::report_rejections() {
  const auto frames = frames_.rejections();
  const auto conditions = conditions_in_.rejections();
  const std::uint64_t no_instance = frames.instances_limit + conditions.instances_limit;
  const std::uint64_t no_room = frames.no_room + conditions.no_room;
  if (no_instance > counts_.rejected_no_instance) {
    spdlog::error("{} frames/condition vectors of asset groups beyond the reader's max_instances refused ({} in all): "
                  "those asset groups are not served; raise max_instances in deploy/dds/qos.xml",
                  no_instance - counts_.rejected_no_instance, no_instance);
  }
  if (no_room > counts_.rejected_no_room) {
    // Back-pressure, not loss: said once at info, then at debug.
    spdlog::log(counts_.rejected_no_room == 0 ? spdlog::level::info : spdlog::level::debug,
                "{} samples refused for lack of room in the reader's history ({} in all); reliable writers resend them",
                no_room - counts_.rejected_no_room, no_room);
  }
  counts_.rejected_no_instance = no_instance;
  counts_.rejected_no_room = no_room;
}

}  // namespace causal::estimator
