// causal-estimator, output side: publishing the filters' output (through the outbound queue), data-quality and
// HEALTH alarms, checkpoints, the output watchdog and the exit summary. The input side is estimator_node.cpp.
#include "estimator_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/sample_limits.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"
#include "wire_bytes.hpp"

#include <spdlog/spdlog.h>

#include <stdexcept>

namespace causal::estimator {

void EstimatorNode::log_condition_report(const std::string& name, const Asset& a, const pipeline::FactorReport& r) {
  const auto* stream = a.pipeline.condition_stream();
  std::string text;
  for (Eigen::Index i = 0; i < r.factors.size(); ++i) {
    text += fmt::format("{}{}={:+.3f}±{:.3f}", i ? " " : "", stream->layout().factor_name(r.outcome, static_cast<int>(i)),
                        r.factors[i], r.std_devs[i]);
  }
  spdlog::info("{} snapshot {} {} {} [{}] NIS {:.2f}: {}", name, r.sample_index, io::format_utc(r.time_ns),
               a.channel_names.at(static_cast<std::size_t>(r.outcome)),
               r.kind == pipeline::EstimateKind::Filter ? "filter" : "fixed-lag", r.nis_mean, text);
}

void EstimatorNode::log_structure(const std::string& name, const Asset& a, const char* level,
                                  const pipeline::LearnedStructure* learned, bool& logged) const {
  if (learned == nullptr || !learned->ready || learned->samples == 0 || logged) return;
  logged = true;
  const auto& names = a.channel_names;
  if (learned->centre.size() > 0) {
    std::string text;
    for (Eigen::Index j = 0; j < learned->centre.size(); ++j) {
      text += fmt::format("{}{}={:.4g}", j ? " " : "", names.at(static_cast<std::size_t>(j)), learned->centre[j]);
    }
    spdlog::info("{} {}: inputs centred on the mean of the first {} samples: {}", name, level, learned->samples, text);
  }
  if (!learned->order.empty()) {
    std::string order, links;
    for (std::size_t p = 0; p < learned->order.size(); ++p) {
      order += (p ? " < " : "") + names.at(static_cast<std::size_t>(learned->order[p]));
    }
    const auto& mask = learned->instantaneous_allowed;
    for (std::size_t k = 0; k < mask.size(); ++k) {
      for (std::size_t j = 0; j < mask[k].size(); ++j) {
        if (j == k || !mask[k][j]) continue;
        links += fmt::format("{}{} -> {} (B0 {:+.3f})", links.empty() ? "" : ", ", names.at(j), names.at(k),
                             learned->b0(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)));
      }
    }
    spdlog::info("{} {}: causal order learned by VAR-LiNGAM on {} samples: {}; instantaneous links: {}", name, level,
                 learned->samples, order, links.empty() ? "none" : links);
  }
  if (!learned->order_summary.empty()) {
    spdlog::log(learned->order_source == "untrusted" ? spdlog::level::warn : spdlog::level::info,
                "{} {}: causal order {}: {}", name, level, learned->order_source, learned->order_summary);
  }
  if (!learned->problem.empty()) spdlog::warn("{} {}: {}", name, level, learned->problem);
}

void EstimatorNode::publish(const std::string& name, Asset& a, bool end_of_snapshot) {
  const std::atomic<bool>& stop = loop_.stop_flag();
  using Class = dds::OutboundQueue::Class;
  struct Item {
    const char* stream;
    Class cls;
    dds::OutboundQueue::WriteFn write;
    std::function<bool()> try_write;  // sample level: written at once when nothing is queued (write_or_push)
  };
  std::vector<Item> items;
  std::vector<std::uint64_t> indices;  // the snapshot (or sample) index of every item
  // The condition-level output kept in the checkpoint: every message not yet acknowledged (UnackedOutput); on a
  // standby (nothing leaves it) the snapshot's own, in `resend`.
  std::vector<std::string> resend;
  const bool keep = end_of_snapshot && store_.enabled(), track = keep && !standing_by_;
  if (track) settle_unacked(a, true);
  auto listed = [&](std::string bytes) {
    return track ? a.unacked.add(std::move(bytes)) : (resend.push_back(std::move(bytes)), UnackedOutput::Flag());
  };
  for (const auto& c : out_.conditions) {
    dds::ConditionHeader h{name, a.feature, c.snapshot_index, c.time_ns, a.channel_names, c.discontinuity};
    auto msg = std::make_shared<causal_twin::ConditionVector>();
    dds::to_condition_vector(h, c.values, *msg);
    UnackedOutput::Flag flag = keep ? listed("C" + to_bytes<causal_twin::ConditionVectorPubSubType>(*msg)) : nullptr;
    items.push_back({"condition_vector", Class::Essential,
                     [this, msg, flag](const std::atomic<bool>& s) { return mark(conditions_out_.write(*msg, s), flag); },
                     nullptr});
    indices.push_back(c.snapshot_index);
  }
  auto send = [&](const std::vector<pipeline::FactorReport>& reports, const pipeline::FactorStream* stream,
                  causal_twin::TimeScale scale, std::uint64_t& counter) {
    if (reports.empty()) return;
    const bool condition = scale == causal_twin::CONDITION_LEVEL;
    dds::FactorContext ctx;
    ctx.asset_group = name;
    ctx.time_scale = scale;
    ctx.feature = condition ? a.feature : "";
    ctx.layout = &stream->layout();
    ctx.channel_names = a.channel_names;
    if (const pipeline::LearnedStructure* learned =
            condition ? a.pipeline.condition_structure() : a.pipeline.sample_structure()) {
      ctx.order_confidence = learned->order_confidence;
      ctx.order_source = learned->order_source;
    }
    // One message per (kind, index) with every outcome's block: G times fewer samples, headers and
    // acknowledgements than one message per outcome (README "Lean data path").
    for (auto& batch : dds::to_causal_factor_batches(ctx, reports)) {
      auto msg = std::make_shared<causal_twin::CausalFactorBatch>(std::move(batch));
      UnackedOutput::Flag flag =
          keep && condition ? listed("B" + to_bytes<causal_twin::CausalFactorBatchPubSubType>(*msg)) : nullptr;
      // Condition-level factors are never dropped; sample-level ones are the stated victims of an overflow.
      items.push_back({condition ? "causal_factors/condition" : "causal_factors/sample",
                       condition ? Class::Essential : Class::Droppable,
                       [this, msg, condition, flag](const std::atomic<bool>& s) {
                         return mark((condition ? factors_ : sample_factors_).write(*msg, s), flag);
                       },
                       nullptr});
      if (!condition) {
        // The sample-level writer never blocks (max_blocking_time 0 in qos.xml): one attempt on this thread.
        items.back().try_write = [this, msg] { return sample_factors_.try_write(*msg) == dds::WriteResult::Ok; };
      }
      if (frame_trace_ && !condition && msg->kind() == causal_twin::FILTER) {
        // Tracing: the write of the frame's filter message (the one readers wait for) is stamped, inline or queued.
        auto& it = items.back();
        it.write = [trace = frame_trace_, write = std::move(it.write)](const std::atomic<bool>& s) {
          trace->write_start_ns = StageTrace::now_ns();
          const auto result = write(s);
          trace->write_end_ns = StageTrace::now_ns();
          return result;
        };
        it.try_write = [trace = frame_trace_, try_write = std::move(it.try_write)] {
          trace->write_start_ns = StageTrace::now_ns();
          const bool ok = try_write();
          if (ok) trace->write_end_ns = StageTrace::now_ns();
          return ok;
        };
      }
      indices.push_back(msg->sample_index());
      ++counter;
    }
    if (condition && options_.verbose) {
      for (const auto& r : reports) log_condition_report(name, a, r);
    }
  };
  send(out_.sample_reports, a.pipeline.sample_stream(), causal_twin::SAMPLE_LEVEL, a.sample_msgs);
  send(out_.condition_reports, a.pipeline.condition_stream(), causal_twin::CONDITION_LEVEL, a.condition_msgs);
  // The checkpoint comes before the output leaves: what a reader received is always covered by it, and the
  // output that may not have left when the process died is in it, to send again.
  if (end_of_snapshot) checkpoint(name, a, track ? a.unacked.list() : resend);
  if (standing_by_) {
    // Kept for a takeover: the condition-level output (essential), by the snapshot it refers to.
    std::vector<StandbyBuffer::Item> kept;
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (items[i].cls != Class::Essential) {
        ++standby_unpublished_;
        continue;
      }
      kept.push_back({items[i].stream, items[i].cls, std::move(items[i].write), indices[i]});
    }
    standby_.retain(name, std::move(kept));
    return;
  }
  if (frame_trace_) frame_trace_->queue_depth = outbound_.size();
  for (auto& item : items) {
    if (item.try_write) outbound_.write_or_push(item.stream, item.cls, item.try_write, std::move(item.write), stop);
    else outbound_.push(item.stream, item.cls, std::move(item.write), stop);
  }
  if (frame_trace_) frame_trace_->queued_ns = StageTrace::now_ns();
  log_structure(name, a, "sample level", a.pipeline.sample_structure(), a.sample_structure_logged);
  log_structure(name, a, "condition level", a.pipeline.condition_structure(), a.condition_structure_logged);
  const auto* s = a.pipeline.sample_stream();
  if (s != nullptr && s->calibrated() && !a.tuning_logged) {
    a.tuning_logged = true;
    for (std::size_t k = 0; k < s->noise().size(); ++k) {
      spdlog::info("{} sample level, outcome {}: q = {:.3g}, r = {:.3g}{}", name, a.channel_names.at(k),
                   s->noise()[k].q, s->noise()[k].r,
                   s->tuning().empty() ? " (fixed)" : " (tuned: " + s->tuning()[k].message + ")");
    }
  }
}

void EstimatorNode::report_rejections() {
  const auto frames = frames_.rejections();
  const auto conditions = conditions_in_.rejections();
  const std::uint64_t no_instance = frames.instances_limit + conditions.instances_limit;
  const std::uint64_t no_room = frames.no_room + conditions.no_room;
  if (no_instance > rejected_no_instance_) {
    spdlog::error("{} frames/condition vectors of asset groups beyond the reader's max_instances refused ({} in all): "
                  "those asset groups are not served; raise max_instances in deploy/dds/qos.xml",
                  no_instance - rejected_no_instance_, no_instance);
  }
  if (no_room > rejected_no_room_) {
    // Back-pressure, not loss: said once at info, then at debug.
    spdlog::log(rejected_no_room_ == 0 ? spdlog::level::info : spdlog::level::debug,
                "{} samples refused for lack of room in the reader's history ({} in all); reliable writers resend them",
                no_room - rejected_no_room_, no_room);
  }
  rejected_no_instance_ = no_instance;
  rejected_no_room_ = no_room;
}

void EstimatorNode::publish_quality(const std::string& name, Asset& a, std::uint64_t snapshot, std::int64_t time_ns,
                                    bool end_of_snapshot) {
  std::vector<causal_twin::Alarm> alarms;
  quality_.on_events(name, a.channel_names, out_.quality_events, snapshot, time_ns, alarms);
  if (end_of_snapshot) quality_.end_of_snapshot(name, snapshot, time_ns, alarms);
  for (const auto& e : out_.quality_events) {
    const bool state = e.kind == pipeline::QualityEventKind::MachineStopped ||
                       e.kind == pipeline::QualityEventKind::MachineRunning;
    spdlog::log(state ? spdlog::level::info : spdlog::level::warn, "asset '{}' {} {}: {}", name,
                pipeline::to_string(e.level), state ? "operating state" : "data quality", e.reason);
  }
  for (auto& alarm : alarms) {
    const bool state = alarm.category() == "operating_change";
    spdlog::log(alarm.state() == causal_twin::CLEARED || state ? spdlog::level::info : spdlog::level::warn, "{} {} {}: {}",
                state ? "OPERATING STATE" : "DATA QUALITY", alarm.state() == causal_twin::CLEARED ? "CLEARED" : "RAISED",
                alarm.alarm_id(), alarm.reason());
    if (standing_by_) continue;  // the primary publishes them
    auto msg = std::make_shared<causal_twin::Alarm>(std::move(alarm));
    outbound_.push("alarm/data_quality", dds::OutboundQueue::Class::Essential,
                   [this, msg](const std::atomic<bool>& s) { return quality_alarms_.write(*msg, s); }, loop_.stop_flag());
  }
}

void EstimatorNode::report_refusal(const std::string& name, std::uint64_t snapshot, std::int64_t time_ns,
                                   const std::string& problem) {
  std::vector<causal_twin::Alarm> alarms;
  if (!quality_.on_refused(name, problem, snapshot, time_ns, alarms)) return;  // raised once per group
  spdlog::error("asset '{}': input refused from snapshot {} on: {}. DATA QUALITY RAISED {}; every refused input is "
                "counted and the estimator exits 4",
                name, snapshot, problem, alarms.front().alarm_id());
  if (standing_by_) return;  // the primary publishes it
  auto msg = std::make_shared<causal_twin::Alarm>(std::move(alarms.front()));
  outbound_.push("alarm/data_quality", dds::OutboundQueue::Class::Essential,
                 [this, msg](const std::atomic<bool>& s) { return quality_alarms_.write(*msg, s); }, loop_.stop_flag());
}

void EstimatorNode::log_adjustments(const std::string& name, Asset& a) {
  if (a.adjustments_logged) return;
  a.adjustments_logged = true;
  for (const auto& adj : a.pipeline.calibration_adjustments()) {
    spdlog::info("asset '{}': {} channels: {} calibration window {} samples instead of the configured {} (the model "
                 "needs {})",
                 name, a.pipeline.channels(), adj.window, adj.used, adj.configured, adj.rule);
  }
}

void EstimatorNode::checkpoint(const std::string& name, Asset& a, const std::vector<std::string>& resend) {
  if (!store_.save(name, a.pipeline, resend, a.last_time_ns)) {
    spdlog::error("asset '{}': checkpoint not written ({}); a crash now would lose this asset group's state", name,
                  store_.last_error());
  }
}

void EstimatorNode::watch_output() {
  // A reader that does not acknowledge (frozen, or far behind) makes the drain thread wait; the filters go on
  // (the outbound queue). Make it visible: a HEALTH alarm while a write has waited longer than stuck_after_s.
  const double blocked = std::chrono::duration<double>(outbound_.blocked_for()).count();
  if (!stuck_alarm_ && blocked > options_.stuck_after_s && !standing_by_) {
    const std::int64_t now_ns = io::utc_now_ns();
    causal_twin::Alarm a;
    a.alarm_id("causal-estimator/output/reader_not_keeping_up/t" + std::to_string(now_ns / 1000000000));
    a.kind("reader_not_keeping_up");
    a.category("health");
    a.severity(causal_twin::WARNING);
    a.state(causal_twin::RAISED);
    a.raised_time_ns(now_ns);
    a.score(blocked);
    a.threshold(options_.stuck_after_s);
    a.reason(fmt::format("a reader of the estimator's output has not acknowledged for {:.1f} s (readers: {}); its "
                         "delivery waits, up to the reader's 5 s lease, the filters go on and {} messages are queued",
                         blocked, fmt::join(participant_.directory().reader_names(dds::topics::kCausalFactors), ", "),
                         outbound_.size()));
    stuck_alarm_ = a;
  } else if (stuck_alarm_ && blocked == 0.0) {
    stuck_alarm_->state(causal_twin::CLEARED);
    stuck_alarm_->cleared_time_ns(io::utc_now_ns());
    stuck_alarm_->reason("every reader acknowledges again");
  } else {
    return;
  }
  const bool cleared = stuck_alarm_->state() == causal_twin::CLEARED;
  spdlog::log(cleared ? spdlog::level::info : spdlog::level::warn, "HEALTH {} {}: {}", cleared ? "CLEARED" : "RAISED",
              stuck_alarm_->alarm_id(), stuck_alarm_->reason());
  // Written directly, not through the (blocked) queue: the alarm writer keeps the last value per id and never waits.
  if (quality_alarms_.write(*stuck_alarm_, loop_.stop_flag()) != dds::WriteResult::Ok)
    spdlog::error("HEALTH {} could not be published (stopping or the alarm writer failed)", stuck_alarm_->alarm_id());
  if (cleared) stuck_alarm_.reset();
}

void EstimatorNode::publish_health() {
  watch_output();
  check_certificate_expiry();
  health_.check(participant_.directory());
  for (auto& alarm : health_.take_alarms()) {
    const bool cleared = alarm.state() == causal_twin::CLEARED;
    spdlog::log(cleared ? spdlog::level::info : spdlog::level::warn, "HEALTH {} {}: {}", cleared ? "CLEARED" : "RAISED",
                alarm.alarm_id(), alarm.reason());
    if (standing_by_) continue;  // the primary publishes them (as with the data-quality alarms)
    auto msg = std::make_shared<causal_twin::Alarm>(std::move(alarm));
    outbound_.push("alarm/health", dds::OutboundQueue::Class::Essential,
                   [this, msg](const std::atomic<bool>& s) { return quality_alarms_.write(*msg, s); }, loop_.stop_flag());
  }
}

int EstimatorNode::finish_all() {
  release_expired_holds(true);     // the source has finished: no continuation will come now
  release_expired_reorders(true);  // the source has finished: what is held goes in, in order
  report_rejections();
  for (auto& [name, a] : assets_) {
    if (!a.refused.empty()) continue;
    // Saved before finish(): a restart continues the streams as they were, not flushed.
    settle_unacked(a);
    checkpoint(name, a, a.unacked.list());
    out_.clear();
    try {
      a.pipeline.finish(out_);
      publish(name, a, false);
    } catch (const std::exception& e) {
      // A shutdown must never crash (SIGTERM included): this group's flush is lost, said and counted.
      a.refused = std::string("flushing at exit failed: ") + e.what();
      ++a.refused_inputs;
      spdlog::error("asset '{}': {}", name, a.refused);
    }
  }
  // Deliver what is queued, then wait for the readers' acknowledgements. After a stop (signal, max runtime)
  // the readers may be leaving too: wait briefly, so shutdown stays bounded.
  const bool stopping = loop_.stopped();
  const auto drain_wait = stopping ? std::chrono::seconds(2) : std::chrono::seconds(30);
  if (!outbound_.drain(drain_wait)) {
    spdlog::warn("{} messages still queued for DDS after {} s: given up (counted as failed)", outbound_.size(),
                 drain_wait.count());
    outbound_.abort();
  }
  const auto ack_wait = stopping ? std::chrono::seconds(1) : std::chrono::seconds(10);
  if (!factors_.wait_for_acknowledgments(ack_wait) || !sample_factors_.wait_for_acknowledgments(ack_wait)) {
    spdlog::warn("not every factor message was acknowledged within {} s", ack_wait.count());
  }
  conditions_out_.wait_for_acknowledgments(ack_wait);

  return log_summary();
}

// The summary: one line per asset group, then machine-readable lines (launch.sh and the tests read them).
int EstimatorNode::log_summary() const {
  std::uint64_t frames = 0, lost = 0, refused = 0, conditions_received = 0, conditions_refused = 0, conditions_late = 0;
  for (const auto& [name, a] : assets_) {
    const auto* s = a.pipeline.sample_stream();
    spdlog::info("asset '{}': {} frames ({} lost, {} refused), {} snapshots lost after a restart, {} condition vectors "
                 "in ({} lost), {} sample-level and {} condition-level factor messages out, {} non-finite rejected",
                 name, a.frames, a.lost_frames, a.refused_frames, a.lost_snapshots, a.conditions_in + a.refused_conditions,
                 a.lost_conditions,
                 a.sample_msgs, a.condition_msgs,
                 s ? s->counters().rejected_non_finite : 0);
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
  if (store_.enabled()) {
    spdlog::info("{} checkpoints written to '{}', {} failed", store_.saves(), options_.state_dir, store_.failures());
  }
  if (foreign_frames_ > 0) {
    spdlog::info("{} frames/condition inputs of other shards received and ignored (the content filter let them "
                 "through: their asset group could not be read)", foreign_frames_);
  }
  if (invalid_msgs_ > 0) spdlog::warn("{} malformed messages refused", invalid_msgs_);
  if (quota_.refused_inputs() > 0) {
    spdlog::error("{} inputs of {} asset groups refused by the quota (--max-groups {}, --max-groups-per-writer {})",
                  quota_.refused_inputs(), quota_.refused_groups(), quota_.limits().max_groups,
                  quota_.limits().max_groups_per_writer);
  }
  std::uint64_t skipped = 0, renumbered = 0;
  for (const auto& [name, a] : assets_) {
    skipped += a.skipped;
    renumbered += a.renumbered;
  }
  // Machine-readable: every input received and not processed, by reason (the tests read it).
  const std::uint64_t not_entitled = not_entitled_frames_ + not_entitled_conditions_;
  if (not_entitled > 0) {
    spdlog::error("{} inputs refused: their writers may not write their asset group ({} writer/group pairs)",
                  not_entitled, grants_.refused_pairs());
  }
  const std::uint64_t dds_refused = dds::refusals_total();  // refused by the readers (sample_limits.hpp)
  spdlog::info("summary not_processed already_processed={} renumbered={} group_quota={} invalid={} not_entitled={} "
               "groups={} dds_refused={}",
               skipped, renumbered, quota_.refused_inputs(), invalid_msgs_, not_entitled, assets_.size(), dds_refused);
  if (!options_.groups.all()) {
    // Machine-readable: the fault test checks that shards divide the groups exactly.
    spdlog::info("summary shard={} groups={} foreign={} filter='{}'", options_.shard_name, assets_.size(),
                 foreign_frames_, options_.groups.expression());
  }
  std::uint64_t published = 0, unpublished = 0;
  const auto streams = outbound_.counters();
  for (const auto& [stream, c] : streams) {
    if (stream.rfind("causal_factors", 0) == 0) published += c.written;
    unpublished += c.dropped + c.failed;
  }
  spdlog::info("causal-estimator: received frames={} groups={} lost={} refused={} rejected_instances={} "
               "rejected_no_room={} published factors={} unpublished={}",
               frames, assets_.size(), lost, refused + invalid_msgs_ + dds_refused, rejected_no_instance_, rejected_no_room_, published,
               unpublished);
  spdlog::info("summary topic=causal_twin/vibration_frame received={} lost={} refused={} not_entitled={}",
               frames + refused + not_entitled_frames_, lost,
               refused + invalid_msgs_ + rejected_no_instance_ + not_entitled_frames_, not_entitled_frames_);
  spdlog::info("summary topic=causal_twin/condition_input received={} refused={} lost={} not_entitled={}",
               conditions_received + conditions_refused + conditions_late + not_entitled_conditions_,
               conditions_refused + not_entitled_conditions_, conditions_late, not_entitled_conditions_);
  // Snapshots whose condition window was dropped (too few usable samples: a channel quarantined for the whole
  // snapshot, a gap): stated here and in the data-quality alarms, never published as a vector.
  std::uint64_t dropped_windows = 0;
  for (const auto& [name, a] : assets_) {
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
  const auto& h = health_.health();
  spdlog::info("summary health sources={} raised={} cleared={} active={} deadline_s={}", h.sources(), h.raised(),
               h.cleared(), h.active_alarms(), h.deadline_s());
  spdlog::info("outbound queue high-water mark: {} of {} messages", outbound_.high_water(), options_.outbound_capacity);
  if (options_.standby) {
    spdlog::info("hot standby: {}; {} sample-level messages not kept while standing by, {} retained messages "
                 "pushed out by newer ones", standing_by_ ? "never took over (the primary stayed)" : "took over",
                 standby_unpublished_, standby_.discarded());
  }
  return (lost + refused + conditions_refused + conditions_late + invalid_msgs_ + rejected_no_instance_ + unpublished +
          dropped_windows + quota_.refused_inputs() + not_entitled + dds_refused) > 0
             ? config::kExitLostOrRefused : config::kExitOk;
}

}  // namespace causal::estimator
