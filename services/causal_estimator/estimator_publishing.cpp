// causal-estimator, publishing: the filters' output through the outbound queue to the writers, the checkpoint
// before a snapshot's output leaves, data-quality and HEALTH alarms, the hot standby. The checkpoint's resend list
// is estimator_resend.cpp; the output watchdog and the certificate alarm are estimator_health.cpp.
#include "estimator_publishing.hpp"

#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/factor_sets.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"
#include "wire_bytes.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

EstimatorPublisher::EstimatorPublisher(dds::Participant& participant, const EstimatorOptions& options,
                                       int condition_fixed_lag, const std::atomic<bool>& stop)
    : participant_(participant),
      options_(options),
      condition_fixed_lag_(condition_fixed_lag),
      stop_(stop),
      factors_(participant_, options_.factor_sets),
      conditions_out_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorWriter),
      quality_alarms_(participant_, dds::topics::kAlarm, dds::profiles::kAlarmWriter),
      store_(options_.state_dir),
      outbound_(options_.outbound_capacity) {
  if (options_.standby) {
    standing_by_ = true;
    primary_progress_ = std::make_unique<dds::TypedReader<causal_twin::ConditionVectorPubSubType>>(
        participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader);
  }
}

std::string EstimatorPublisher::wait_for_readers(const std::vector<dds::NamedReaders>& wanted,
                                                 std::chrono::milliseconds timeout) {
  return factors_.wait_for_readers(wanted, timeout, stop_);
}

void EstimatorPublisher::start() {
  primary_seen_ = std::chrono::steady_clock::now();
  if (standing_by_) spdlog::info("hot standby: publishing nothing while a primary causal-estimator is alive");
}

void EstimatorPublisher::watch_primary() {
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
  const auto margin = static_cast<std::uint64_t>(std::max(0, condition_fixed_lag_)) + 2;
  auto items = standby_.take_over(margin);
  spdlog::warn("no primary causal-estimator for {:.0f} s: taking over; {} retained messages published again from {} "
               "snapshots before the primary's last one (readers drop what they have)",
               options_.takeover_after_s, items.size(), margin);
  for (auto& item : items) outbound_.push(item.stream, item.cls, std::move(item.write), stop_);
}

void EstimatorPublisher::publish(const std::string& name, GroupState& a, const pipeline::PipelineOutput& out,
                                 bool end_of_snapshot, const std::shared_ptr<StageTrace::Frame>& trace) {
  using Class = dds::OutboundQueue::Class;
  std::vector<Item> items;
  // The condition-level output kept in the checkpoint: every message not yet acknowledged (UnackedOutput); on a
  // standby (nothing leaves it) the snapshot's own, in `resend`.
  std::vector<std::string> resend;
  const bool keep = end_of_snapshot && store_.enabled(), track = keep && !standing_by_;
  if (track) settle_unacked(a, true);
  std::function<UnackedOutput::Flag(std::string)> listed;
  if (keep) {
    listed = [&](std::string bytes) {
      return track ? a.unacked.add(std::move(bytes)) : (resend.push_back(std::move(bytes)), UnackedOutput::Flag());
    };
  }
  for (const auto& c : out.conditions) {
    dds::ConditionHeader h{name, a.feature, c.snapshot_index, c.time_ns, a.channel_names, c.discontinuity};
    auto msg = std::make_shared<causal_twin::ConditionVector>();
    dds::to_condition_vector(h, c.values, *msg);
    UnackedOutput::Flag flag = keep ? listed("C" + to_bytes<causal_twin::ConditionVectorPubSubType>(*msg)) : nullptr;
    items.push_back({"condition_vector", Class::Essential,
                     [this, msg, flag](const std::atomic<bool>& s) { return mark(conditions_out_.write(*msg, s), flag); },
                     nullptr, c.snapshot_index});
  }
  factor_items(name, a, out.sample_reports, false, listed, trace, items);
  factor_items(name, a, out.condition_reports, true, listed, trace, items);
  // The checkpoint comes before the output leaves: what a reader received is always covered by it, and the
  // output that may not have left when the process died is in it, to send again.
  if (end_of_snapshot) checkpoint(name, a, track ? a.unacked.list() : resend);
  send_items(name, items, trace);
}

void EstimatorPublisher::factor_items(const std::string& name, GroupState& a,
                                      const std::vector<pipeline::FactorReport>& reports, bool condition,
                                      const std::function<UnackedOutput::Flag(std::string)>& listed,
                                      const std::shared_ptr<StageTrace::Frame>& trace, std::vector<Item>& items) {
  if (reports.empty()) return;
  const pipeline::FactorStream* stream = condition ? a.pipeline.condition_stream() : a.pipeline.sample_stream();
  dds::FactorContext ctx;
  ctx.asset_group = name;
  ctx.time_scale = condition ? causal_twin::CONDITION_LEVEL : causal_twin::SAMPLE_LEVEL;
  ctx.feature = condition ? a.feature : "";
  ctx.layout = &stream->layout();
  ctx.channel_names = a.channel_names;
  if (const pipeline::LearnedStructure* learned =
          condition ? a.pipeline.condition_structure() : a.pipeline.sample_structure()) {
    ctx.order_confidence = learned->order_confidence;
    ctx.order_source = learned->order_source;
  }
  std::uint64_t& counter = condition ? a.condition_msgs : a.sample_msgs;
  // One message per (kind, index) with every outcome's block: G times fewer samples, headers and
  // acknowledgements than one message per outcome (README "Lean data path").
  auto batches = dds::to_causal_factor_batches(ctx, reports);
  counter += batches.size();
  if (!factors_.sets()) {
    for (auto& batch : batches) {
      auto msg = std::make_shared<causal_twin::CausalFactorBatch>(std::move(batch));
      UnackedOutput::Flag flag =
          listed && condition ? listed("B" + to_bytes<causal_twin::CausalFactorBatchPubSubType>(*msg)) : nullptr;
      const bool traced = !condition && msg->kind() == causal_twin::FILTER;
      factor_item(msg, condition, msg->sample_index(), flag, traced ? trace : nullptr, items);
    }
    log_condition_reports(name, a, reports, condition);
    return;
  }
  // One set per input (and level): its batches in the order they would be written one by one.
  for (std::size_t first = 0; first < batches.size(); first += dds::kFactorSetMaxBatches) {
    auto set = std::make_shared<causal_twin::CausalFactorSet>();
    set->asset_group(name);
    set->time_scale(ctx.time_scale);
    set->version(dds::kFactorSetVersion);
    std::uint64_t index = 0;  // the newest index in it (a standby's takeover keeps what may be missing)
    bool filter = false;
    for (std::size_t i = first; i < std::min(batches.size(), first + dds::kFactorSetMaxBatches); ++i) {
      index = std::max<std::uint64_t>(index, batches[i].sample_index());
      filter = filter || batches[i].kind() == causal_twin::FILTER;
      set->batches().push_back(std::move(batches[i]));
    }
    UnackedOutput::Flag flag =
        listed && condition ? listed("S" + to_bytes<causal_twin::CausalFactorSetPubSubType>(*set)) : nullptr;
    factor_item(set, condition, index, flag, !condition && filter ? trace : nullptr, items);
    ++(condition ? a.condition_sets : a.sample_sets);
  }
  log_condition_reports(name, a, reports, condition);
}

template <typename Msg>
void EstimatorPublisher::factor_item(std::shared_ptr<Msg> msg, bool condition, std::uint64_t index,
                                     UnackedOutput::Flag flag, const std::shared_ptr<StageTrace::Frame>& traced,
                                     std::vector<Item>& items) {
  using Class = dds::OutboundQueue::Class;
  const bool sets = factors_.sets();
  // Condition-level factors are never dropped; sample-level ones are the stated victims of an overflow.
  items.push_back({condition ? (sets ? "causal_factor_sets/condition" : "causal_factors/condition")
                             : (sets ? "causal_factor_sets/sample" : "causal_factors/sample"),
                   condition ? Class::Essential : Class::Droppable,
                   [this, msg, condition, flag](const std::atomic<bool>& s) {
                     return mark(factors_.write(condition, *msg, s), flag);
                   },
                   nullptr, index});
  if (!condition) {
    // The sample-level writer never blocks (max_blocking_time 0 in qos.xml): one attempt on this thread.
    items.back().try_write = [this, msg] { return factors_.try_write(*msg); };
  }
  if (traced) {
    // Tracing: the write of the frame's filter message (the one readers wait for) is stamped, inline or queued.
    auto& it = items.back();
    it.write = [trace = traced, write = std::move(it.write)](const std::atomic<bool>& s) {
      trace->write_start_ns = StageTrace::now_ns();
      const auto result = write(s);
      trace->write_end_ns = StageTrace::now_ns();
      return result;
    };
    it.try_write = [trace = traced, try_write = std::move(it.try_write)] {
      trace->write_start_ns = StageTrace::now_ns();
      const bool ok = try_write();
      if (ok) trace->write_end_ns = StageTrace::now_ns();
      return ok;
    };
  }
}

void EstimatorPublisher::log_condition_reports(const std::string& name, const GroupState& a,
                                               const std::vector<pipeline::FactorReport>& reports,
                                               bool condition) const {
  if (condition && options_.verbose) {
    for (const auto& r : reports) log_condition_report(name, a, r);
  }
}

void EstimatorPublisher::send_items(const std::string& name, std::vector<Item>& items,
                                    const std::shared_ptr<StageTrace::Frame>& trace) {
  if (standing_by_) {
    // Kept for a takeover: the condition-level output (essential), by the snapshot it refers to.
    std::vector<StandbyBuffer::Item> kept;
    for (auto& item : items) {
      if (item.cls != dds::OutboundQueue::Class::Essential) {
        ++standby_unpublished_;
        continue;
      }
      kept.push_back({item.stream, item.cls, std::move(item.write), item.index});
    }
    standby_.retain(name, std::move(kept));
    return;
  }
  if (trace) trace->queue_depth = outbound_.size();
  for (auto& item : items) {
    if (item.try_write) outbound_.write_or_push(item.stream, item.cls, item.try_write, std::move(item.write), stop_);
    else outbound_.push(item.stream, item.cls, std::move(item.write), stop_);
  }
  if (trace) trace->queued_ns = StageTrace::now_ns();
}

void EstimatorPublisher::log_condition_report(const std::string& name, const GroupState& a,
                                              const pipeline::FactorReport& r) const {
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

void EstimatorPublisher::publish_quality(const std::string& name, const GroupState& a,
                                         const pipeline::PipelineOutput& out, std::uint64_t snapshot,
                                         std::int64_t time_ns, bool end_of_snapshot) {
  std::vector<causal_twin::Alarm> alarms;
  quality_.on_events(name, a.channel_names, out.quality_events, snapshot, time_ns, alarms);
  if (end_of_snapshot) quality_.end_of_snapshot(name, snapshot, time_ns, alarms);
  for (const auto& e : out.quality_events) {
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
    push_alarm("alarm/data_quality", std::move(alarm));
  }
}

void EstimatorPublisher::report_refusal(const std::string& name, std::uint64_t snapshot, std::int64_t time_ns,
                                        const std::string& problem) {
  std::vector<causal_twin::Alarm> alarms;
  if (!quality_.on_refused(name, problem, snapshot, time_ns, alarms)) return;  // raised once per group
  spdlog::error("asset '{}': input refused from snapshot {} on: {}. DATA QUALITY RAISED {}; every refused input is "
                "counted and the estimator exits 4",
                name, snapshot, problem, alarms.front().alarm_id());
  if (standing_by_) return;  // the primary publishes it
  push_alarm("alarm/data_quality", std::move(alarms.front()));
}

void EstimatorPublisher::raise_input_alarm(const std::string& asset_group, const std::string& kind,
                                           causal_twin::Severity severity, std::size_t serial, double score,
                                           double threshold, const std::string& reason) {
  causal_twin::Alarm alarm;
  const std::int64_t now = io::utc_now_ns();
  // Wall-clock time and a per-kind serial: a refusal has no source index of its own.
  alarm.alarm_id(fmt::format("{}/input/{}/t{}.{}", asset_group, kind, now / 1000000000, serial));
  alarm.asset_group(asset_group);
  alarm.kind(kind);
  alarm.category("health");
  alarm.severity(severity);
  alarm.state(causal_twin::RAISED);
  alarm.raised_time_ns(now);
  alarm.score(score);
  alarm.threshold(threshold);
  alarm.reason(reason);
  publish_health_alarm(std::move(alarm));
}

void EstimatorPublisher::publish_health_alarm(causal_twin::Alarm alarm) {
  spdlog::warn("HEALTH RAISED {}: {}", alarm.alarm_id(), alarm.reason());
  if (standing_by_) return;  // the active estimator raises it
  push_alarm("alarm/health", std::move(alarm));
}

void EstimatorPublisher::push_alarm(const char* stream, causal_twin::Alarm alarm) {
  auto msg = std::make_shared<causal_twin::Alarm>(std::move(alarm));
  outbound_.push(stream, dds::OutboundQueue::Class::Essential,
                 [this, msg](const std::atomic<bool>& s) { return quality_alarms_.write(*msg, s); }, stop_);
}

void EstimatorPublisher::checkpoint(const std::string& name, GroupState& a, const std::vector<std::string>& resend) {
  if (!store_.save(name, a.pipeline, resend, a.last_time_ns)) {
    spdlog::error("asset '{}': checkpoint not written ({}); a crash now would lose this asset group's state", name,
                  store_.last_error());
  }
}

void EstimatorPublisher::checkpoint_at_exit(const std::string& name, GroupState& a) {
  settle_unacked(a);
  checkpoint(name, a, a.unacked.list());
}

void EstimatorPublisher::finish(bool stopping) {
  // Deliver what is queued, then wait for the readers' acknowledgements. After a stop (signal, max runtime)
  // the readers may be leaving too: wait briefly, so shutdown stays bounded.
  const auto drain_wait = stopping ? std::chrono::seconds(2) : std::chrono::seconds(30);
  if (!outbound_.drain(drain_wait)) {
    spdlog::warn("{} messages still queued for DDS after {} s: given up (counted as failed)", outbound_.size(),
                 drain_wait.count());
    outbound_.abort();
  }
  const auto ack_wait = stopping ? std::chrono::seconds(1) : std::chrono::seconds(10);
  if (!factors_.acknowledged(ack_wait)) {
    spdlog::warn("not every factor message was acknowledged within {} s", ack_wait.count());
  }
  conditions_out_.wait_for_acknowledgments(ack_wait);
}

}  // namespace causal::estimator
