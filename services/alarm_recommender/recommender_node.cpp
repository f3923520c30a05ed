#include "recommender_node.hpp"

#include "advice_conversions.hpp"
#include "prognosis_conversions.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"

#include "causal/metrics/metrics_registry.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

namespace causal::recommender {

RecommenderNode::RecommenderNode(RecommenderOptions options, RecommenderParams params)
    : options_(std::move(options)),
      params_(std::move(params)),
      participant_(dds::to_dds_settings(options_.dds, "alarm-recommender")),
      factors_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsReader),
      factor_sets_(dds::make_factor_set_reader(participant_)),
      conditions_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader),
      whatif_requests_(participant_, dds::topics::kWhatIfRequest, dds::profiles::kWhatIfReader),
      alarms_(participant_, dds::topics::kAlarm, dds::profiles::kAlarmWriter),
      recommendations_(participant_, dds::topics::kRecommendation, dds::profiles::kRecommendationWriter),
      whatif_replies_(participant_, dds::topics::kWhatIfReply, dds::profiles::kWhatIfWriter),
      status_writer_(participant_, dds::topics::kAssetStatus, dds::profiles::kAssetStatusWriter),
      prognoses_(participant_, dds::topics::kPrognosis, dds::profiles::kPrognosisWriter),
      action_desk_(participant_, options_.state_dir),
      desk_(params_, options_.state_dir),
      interventions_(participant_, desk_.outcome_check()),
      recommendation_store_(options_.state_dir),
      alarm_message_store_(options_.state_dir),
      health_(params_.health_deadline_s, "causal factors", "estimator",
              {dds::topics::kCausalFactors, dds::topics::kCausalFactorSets}) {
  loop_.attach(factors_.get());
  if (factor_sets_) loop_.attach(factor_sets_->get());
  loop_.attach(conditions_.get());
  loop_.attach(whatif_requests_.get());
  loop_.attach(action_desk_.reader().get());
  interventions_.attach(loop_);
}

int RecommenderNode::run() {
  spdlog::info("alarm-recommender on domain {}, waiting for causal factors", participant_.domain_id());
  if (const int rc = wait_for_readers(); rc != 0) return rc;
  restore_checkpoints();
  // ready: being judged; later: taken meanwhile (judged by the next poll; what-if requests and alarm actions are
  // answered after every observation, take_operator_requests).
  std::vector<AssembledObservation> ready, later;
  // Everything the readers hold is taken into the assembler, whose observations become `into` (appended).
  const auto take = [&](std::vector<AssembledObservation>& into) {
    std::size_t n = interventions_.take();  // before the data: an approval is frozen at its start's eve
    n += conditions_.take_all([&](const causal_twin::ConditionVector& c, const auto&) {
      if (!dds::validate_condition_vector(c).empty()) {
        ++invalid_msgs_;
        return;
      }
      ++conditions_received_;
      assembler_.add_condition(c.asset_group(), c.feature(), c.time_ns(), dds::values_of(c), c.discontinuity(), into);
    });
    n += take_factors(into);
    return n;
  };
  const auto poll = [&] {
    const bool sources_gone = factors_.matched_writers() + conditions_.matched_writers() == 0;  // before the take
    std::size_t data = take(later);
    ready.swap(later);
    later.clear();
    std::size_t n = ready.size();  // judging is activity too: --idle-exit counts from its end
    handle(ready, [&] { data += take(later); n += take_operator_requests(); });
    publish_health();
    n += take_operator_requests();
    note_caught_up(sources_gone, data);
    return n + data;
  };
  // Idle exit only once every source has left the domain (see causal-estimator).
  const auto end = loop_.run({options_.idle_exit_s, options_.max_runtime_s}, poll,
                             [this] { return factors_.matched_writers() + dds::matched_writers(factor_sets_) + conditions_.matched_writers(); });
  if (end == dds::RunEnd::Idle) spdlog::info("all sources gone and no data for {:.1f} s: finishing", options_.idle_exit_s);
  if (end == dds::RunEnd::MaxRuntime) spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
  assembler_.flush(later);
  handle(later, [] {});
  interventions_.finish();
  for (auto& alarm : interventions_.take_health_alarms()) publish_health_alarm(alarm);  // refused at the end
  auto& store = desk_.store();
  store.flush();
  for (const auto& error : store.take_errors()) spdlog::error("{}", error);
  for (const auto& e : desk_.summaries()) {
    spdlog::info("asset '{}' {} level: {} observations, {} alarms raised, {} still active, {} discontinuities, "
                 "{} operating changes re-baselined", e.asset_group, advice::to_string(e.time_scale), e.observations,
                 e.raised, e.active, e.discontinuities, e.operating_changes);
  }
  if (invalid_msgs_ > 0) spdlog::warn("{} malformed messages refused", invalid_msgs_);
  spdlog::info("{} re-sent observations dropped (index not after the last one processed)", store.duplicates());
  if (store.enabled()) {
    spdlog::info("{} checkpoints written to '{}', {} failed; alarm messages: {} not written, {} re-published "
                 "without their decision; recommendations: {} not written", store.saves(), options_.state_dir,
                 store.save_failures(), alarm_message_store_.save_failures(), decisions_not_kept_,
                 recommendation_store_.save_failures());
  }
  if (const auto c = assembler_.factor_counters(); c.dropped + c.duplicates + c.refused > 0) {
    spdlog::warn("causal factors: {} messages assembled into {} observations; {} duplicates (re-sent or replayed "
                 "indices, dropped), {} refused{}, {} factor sets never completed (lost outcome messages)",
                 c.accepted, c.complete, c.duplicates, c.refused,
                 c.refused > 0 ? " (last: " + assembler_.last_problem() + ")" : std::string(), c.dropped);
  }
  if (assembler_.evicted_conditions() > 0) {
    spdlog::warn("{} condition vectors dropped before their causal factors came (more than the assembler keeps "
                 "waiting): their observations were judged without features", assembler_.evicted_conditions());
  }
  if (!alarms_.wait_for_acknowledgments(std::chrono::seconds(10))) {
    spdlog::warn("not every alarm was acknowledged within 10 s");
  }
  recommendations_.wait_for_acknowledgments(std::chrono::seconds(10));
  prognoses_.wait_for_acknowledgments(std::chrono::seconds(10));
  spdlog::info("{} alarm messages, {} recommendations and {} prognoses published", alarms_published_,
               recommendations_published_, prognoses_published_);
  spdlog::info("summary advice events={} act_on_asset={} upstream_lever={}", events_advised_, events_act_on_asset_,
               events_upstream_lever_);
  // Samples refused for lack of room are resent by the reliable writers (back-pressure); refused instances and
  // lost samples are not.
  const std::uint64_t dds_lost = factors_.rejections().instances_limit + factors_.lost_samples() +
                                 (factor_sets_ ? factor_sets_->rejections().instances_limit + factor_sets_->lost_samples() : 0) +
                                 conditions_.rejections().instances_limit + conditions_.lost_samples();
  spdlog::info("summary topic=causal_twin/causal_factors received={} rejected={} lost={}", factors_received_,
               invalid_msgs_, observations_lost_);
  if (factor_set_counts_.received > 0) {  // their batches are counted in the line above
    spdlog::info("summary topic=causal_twin/causal_factor_sets received={} batches={} refused={}",
                 factor_set_counts_.received, factor_set_counts_.batches, factor_set_counts_.refused);
  }
  spdlog::info("summary topic=causal_twin/condition_vector received={}", conditions_received_);
  spdlog::info("summary topic=causal_twin/alarm sent={}", alarms_published_);
  const auto& h = health_.health();
  spdlog::info("summary health sources={} raised={} cleared={} active={} deadline_s={}", h.sources(), h.raised(),
               h.cleared(), h.active_alarms(), h.deadline_s());
  spdlog::info("summary topic=causal_twin/recommendation sent={}", recommendations_published_);
  status_writer_.wait_for_acknowledgments(std::chrono::seconds(2));
  spdlog::info("summary topic=causal_twin/asset_status sent={} failed={}", statuses_published_, status_write_failures_);
  spdlog::info("summary topic=causal_twin/prognosis sent={} failed={}", prognoses_published_, prognosis_write_failures_);
  action_desk_.log_summary();
  if (dds_lost > 0) spdlog::warn("summary dds: {} input samples rejected or lost by the readers", dds_lost);
  log_whatif_summary();
  return (invalid_msgs_ + factor_set_counts_.refused + dds_lost + assembler_.dropped_incomplete() + assembler_.evicted_conditions() +
          status_write_failures_ + whatif_not_entitled_ + action_desk_.result_write_failures() +
          action_desk_.checkpoint_failures() + action_desk_.not_entitled() + interventions_.not_entitled()) > 0
             ? config::kExitLostOrRefused
             : config::kExitOk;
}

void RecommenderNode::publish_health() {
  health_.check(participant_.directory());
  for (auto& alarm : health_.take_alarms()) publish_health_alarm(alarm);
  for (auto& alarm : interventions_.take_health_alarms()) publish_health_alarm(alarm);  // refused approvals' writers
}

void RecommenderNode::handle(std::vector<AssembledObservation>& ready, const std::function<void()>& take_more) {
  // The readers are emptied after every observation, so a slow one (an alarm's what-if draws at a wide group)
  // never leaves the writers blocked on full reader histories (64 samples per group): the estimator's output
  // then waits at most its bounded drain at exit, and what it sent is kept here (the assembler) until judged.
  for (auto& a : ready) {
    observe(a);
    ++observations_judged_;
    take_more();
  }
}

void RecommenderNode::observe(AssembledObservation& a) {
  const advice::Judgement j = desk_.judge(a);
  publish_judgement(a, j);
}

// The output edge: the desk's judgement published on the alarm, recommendation, prognosis and asset status topics
// and logged, in the order the chain produced it. The desk has already written the checkpoint, so every event
// published here is one a restart can publish again.
void RecommenderNode::publish_judgement(const AssembledObservation& a, const advice::Judgement& j) {
  const char* scale = advice::to_string(a.time_scale);
  if (j.opened && j.resumed) {  // its file appeared after the start (restore_checkpoints published the others)
    publish_resumed(j.resumed_from);
  } else if (j.opened) {
    spdlog::info("asset '{}' {} level: learning the baseline from the first {} observations", a.asset_group, scale,
                 j.learning_observations);
  }
  if (j.duplicate) {
    spdlog::debug("asset '{}' {} level: observation {} already processed (re-sent), dropped", a.asset_group, scale,
                  a.observation.index);
    return;
  }
  if (!j.judged) return;
  interventions_.publish_finished(a.asset_group, a.channel_names, j.finished_outcomes);
  if (j.covariance_changed) {
    spdlog::info("asset '{}': what-if intervals from {}", a.asset_group,
                 j.full_covariance ? "the full per-outcome factor covariance"
                                   : "factor standard deviations only (no covariance blocks: correlations ignored)");
  }
  if (j.observations_lost > 0) {
    observations_lost_ += j.observations_lost;
    metrics::process_metrics()
        .counter("recommender_observations_lost_total",
                 "Observations the alarm engines saw skipped by a consecutively numbered source (input lost)",
                 {{"asset_group", a.asset_group}, {"time_scale", scale}})
        .inc(static_cast<double>(j.observations_lost));
  }
  if (j.trend_values_refused > 0) {
    spdlog::warn("asset '{}': {} feature values refused by the prognosis trends at observation {} ({} so far)",
                 a.asset_group, j.trend_values_refused, a.observation.index, j.trend_values_refused_total);
  }
  for (const auto& error : j.checkpoint_errors) spdlog::error("{}", error);
  for (const auto& e : j.events) {
    publish_event(a, e);
    if (e.advised) recommend(a, e);
  }
  if (j.prognoses_judged) publish_prognoses(a.asset_group, j.prognoses);
  publish_status(a, j.status);
  if (j.baseline_learned) {
    spdlog::info("asset '{}' {} level: baseline learned, monitoring from observation {}", a.asset_group, scale,
                 a.observation.index);
  }
}

void RecommenderNode::publish_resumed(const advice::Resumed& r) {
  spdlog::info("asset '{}' {} level: resumed from checkpoint: {} observations, {} active alarms", r.asset_group,
               advice::to_string(r.time_scale), r.observations, r.active_alarms);
  republish(r.asset_group, r.channel_names, r.republish);
  if (r.prognoses_judged) publish_prognoses(r.asset_group, r.prognoses);
}

void RecommenderNode::republish(const std::string& asset_group, const std::vector<std::string>& channel_names,
                                const std::vector<alarms::AlarmEvent>& events) {
  // Transient-local readers that join after the restart must see the alarms raised before it, with the decision
  // (action, next level) they carried when published: kept beside the engine checkpoint, which has the events only.
  std::size_t without_decision = 0;
  causal_twin::Alarm kept;
  for (const auto& e : events) {
    dds::to_alarm(asset_group, channel_names, e, alarm_msg_);
    if (!alarm_message_store_.find(asset_group, e.alarm_id, kept) || !restore_decision(kept, alarm_msg_)) {
      if (e.category == alarms::category::kDegradation && e.state != alarms::AlarmState::Cleared) ++without_decision;
    }
    action_desk_.on_publish(alarm_msg_, true);
    if (alarms_.write(alarm_msg_, loop_.stop_flag()) == dds::WriteResult::Ok) {
      ++alarms_published_;
      open_alarms_.on_published(alarm_msg_);
    }
  }
  spdlog::info("asset '{}': {} alarm messages re-published from the checkpoint", asset_group, events.size());
  if (without_decision > 0) {  // the process died after the engine checkpoint, before the message was kept
    decisions_not_kept_ += without_decision;
    spdlog::warn("asset '{}': {} open alarm(s) re-published without their action: not kept before the restart "
                 "(the next escalation carries one again)", asset_group, without_decision);
  }
}

void RecommenderNode::publish_event(const AssembledObservation& a, const advice::EventJudgement& j) {
  const alarms::AlarmEvent& e = j.event;
  dds::to_alarm(a.asset_group, a.channel_names, e, alarm_msg_);
  if (j.has_next_level) {
    set_next_level(j.next_level, alarm_msg_);
    spdlog::info("PROGNOSIS {}: {}", e.alarm_id, j.next_level_text);
  }
  alarm_msg_.action(j.advised ? j.decision.action : std::string());
  alarm_message_store_.record(alarm_msg_);  // kept before it is published, as the engine checkpoint
  action_desk_.on_publish(alarm_msg_);
  if (alarms_.write(alarm_msg_, loop_.stop_flag()) == dds::WriteResult::Ok) {
    ++alarms_published_;
    open_alarms_.on_published(alarm_msg_);
  }
  const auto level = e.severity == alarms::Severity::Critical  ? spdlog::level::err
                     : e.severity == alarms::Severity::Warning ? spdlog::level::warn
                                                               : spdlog::level::info;
  if (e.category == alarms::category::kHealth) {  // input the engine never received (input_continuity.hpp)
    if (e.state == alarms::AlarmState::Raised) spdlog::warn("HEALTH RAISED {}: {}", e.alarm_id, e.reason);
    return;
  }
  if (e.category != alarms::category::kDegradation) {  // an operating change: re-baselined, not a fault
    if (e.state == alarms::AlarmState::Raised)
      spdlog::info("OPERATING CHANGE {} {}: {}", e.alarm_id, alarm_msg_.channel_name(), e.reason);
    return;
  }
  spdlog::log(level, "ALARM {} {} [{} {}, root cause {} confidence {:.2f}] {}: {}", alarms::to_string(e.state),
              e.alarm_id, alarms::to_string(e.severity),
              a.time_scale == advice::TimeScale::Sample ? "sample-level" : "condition-level",
              alarm_msg_.root_cause_name(), e.root_cause_confidence, alarm_msg_.channel_name(), e.reason);
}

void RecommenderNode::recommend(const AssembledObservation& a, const advice::EventJudgement& j) {
  const Decision& d = j.decision;
  const alarms::AlarmEvent& e = j.event;
  ++events_advised_;
  ++(d.kind == "upstream_lever" ? events_upstream_lever_ : events_act_on_asset_);
  RecommendationContext ctx;
  ctx.asset_group = a.asset_group;
  ctx.alarm_id = e.alarm_id;
  ctx.sample_index = e.index;
  // A raise keeps the id "<alarm_id>/<rank>"; each escalation gets its own instance, so none replaces another.
  ctx.id_prefix = e.state == alarms::AlarmState::Raised ? e.alarm_id : e.alarm_id + "@" + std::to_string(e.index);
  ctx.action_kind = d.kind;
  ctx.act_on_channel = d.act_on;
  ctx.act_on_name = a.channel_names.at(static_cast<std::size_t>(d.act_on));
  ctx.order_confidence = j.trust.confidence;
  ctx.order_source = j.trust.source;
  causal_twin::Recommendation msg;
  for (const auto& item : d.items) {
    if (item.rank > params_.advice.max_per_alarm) break;
    ctx.action = item.action;
    ctx.horizon_hours = item.diag.kind == "horizon" ? item.diag.horizon_snapshots * j.snapshot_hours : NAN;
    to_recommendation(ctx, item, msg);
    withdraw_if_untrusted(interventions_, msg);  // a lever whose intervention outcomes missed is not claimed
    recommendation_store_.record(msg);  // kept before it is published, as the alarm events
    if (recommendations_.write(msg, loop_.stop_flag()) == dds::WriteResult::Ok) ++recommendations_published_;
    spdlog::info("RECOMMENDATION {} at {} #{} [{}, act on {}]: {}", e.alarm_id, e.index, item.rank, d.kind,
                 ctx.act_on_name, item.text);
  }
  status_.note_action(e.alarm_id, d.action);  // the operator's status line shows the latest action
}

void RecommenderNode::publish_prognoses(const std::string& asset_group,
                                        const std::vector<advice::PrognosisLine>& lines) {
  prognosis_metrics_.begin(asset_group);
  for (const auto& line : lines) {
    to_prognosis(asset_group, line, params_.prognosis.coverage, prognosis_msg_);
    if (prognoses_.write(prognosis_msg_, loop_.stop_flag()) == dds::WriteResult::Ok) {
      ++prognoses_published_;
      prognosis_metrics_.on_published(prognosis_msg_);
    } else if (prognosis_write_failures_++ % 100 == 0) {
      spdlog::warn("prognosis for '{}' channel {} not published ({} failures so far)", asset_group,
                   line.prognosis.channel + 1, prognosis_write_failures_);
    }
    spdlog::debug("PROGNOSIS {}", prognosis_msg_.text());
  }
  prognosis_metrics_.end(asset_group);
}

// The AssetStatus line of the group (asset_status.hpp), published on causal_twin/asset_status when it changes
// (transient-local, last value per group: a view that joins later gets every group's state).
void RecommenderNode::publish_status(const AssembledObservation& a, const advice::StatusFacts& facts) {
  StatusInput in(facts);
  in.management = [this](causal_twin::AssetStatus& s) { action_desk_.fill(s); };
  causal_twin::AssetStatus msg;
  if (!status_.update(a.asset_group, in, msg)) return;
  const bool learning = msg.state() == "learning";
  // Learning advances at every observation: logged at debug, the other states when they change.
  spdlog::log(learning ? spdlog::level::debug : spdlog::level::info, "STATUS {} {}: {}", a.asset_group, msg.state(),
              msg.text());
  const dds::WriteResult r = status_writer_.write(msg, loop_.stop_flag());
  if (r == dds::WriteResult::Ok) {
    ++statuses_published_;
  } else if (r != dds::WriteResult::Stopped && status_write_failures_++ % 100 == 0) {
    // A reader that stays behind past the give-up time (not a stop): counted, logged and in the exit code.
    spdlog::warn("asset status of '{}' not published ({} failures so far)", a.asset_group, status_write_failures_);
  }
}

void RecommenderNode::restore_checkpoints() {
  alarm_message_store_.load_all();  // before the engines: republish() takes each alarm's decision from it
  for (const auto& r : desk_.restore()) publish_resumed(r);
  const auto recommendations = recommendation_store_.load_all();
  for (auto r : recommendations) {
    if (recommendations_.write(r, loop_.stop_flag()) == dds::WriteResult::Ok) ++recommendations_published_;
  }
  if (!recommendations.empty()) {
    spdlog::info("{} recommendations re-published from the checkpoint", recommendations.size());
  }
}

void RecommenderNode::answer(const causal_twin::WhatIfRequest& request) {
  const auto ans = desk_.advisor().what_if(request.asset_group(), static_cast<int>(request.intervene_channel()) - 1,
                                    request.delta(), request.sustained());
  causal_twin::WhatIfReply reply;
  to_whatif_reply(request, ans, reply);
  if (whatif_replies_.write(reply, loop_.stop_flag()) != dds::WriteResult::Ok) {
    spdlog::error("what-if {}: the reply could not be published (stopping or the writer failed)", request.request_id());
  }
  spdlog::info("what-if {} on '{}': {}", request.request_id(), request.asset_group(), ans.ok ? ans.text : ans.error);
}

}  // namespace causal::recommender
