#include "recommender_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "advice_conversions.hpp"
#include "prognosis_conversions.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

namespace causal::recommender {

namespace {

bool has_open_degradation(const alarms::AlarmEngine& engine) {
  for (const auto& e : engine.active_alarms()) {
    if (e.category == alarms::category::kDegradation) return true;
  }
  return false;
}

}  // namespace

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
      interventions_(participant_, params_.advice.model_log_features),
      advisor_(params_.advice),
      store_(options_.state_dir),
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
  store_.flush();
  for (const auto& [key, st] : engines_) {
    const auto active = st.engine->active_alarms();
    spdlog::info("asset '{}' {} level: {} observations, {} alarms raised, {} still active, {} discontinuities, "
                 "{} operating changes re-baselined", key.first,
                 key.second == causal_twin::SAMPLE_LEVEL ? "sample" : "condition", st.engine->observations_seen(),
                 st.raised, active.size(), st.engine->discontinuities(), st.engine->operating_changes());
  }
  if (invalid_msgs_ > 0) spdlog::warn("{} malformed messages refused", invalid_msgs_);
  spdlog::info("{} re-sent observations dropped (index not after the last one processed)", store_.duplicates());
  if (store_.enabled()) {
    spdlog::info("{} checkpoints written to '{}', {} failed; alarm messages: {} not written, {} re-published "
                 "without their decision; recommendations: {} not written", store_.saves(), options_.state_dir,
                 store_.save_failures(), alarm_message_store_.save_failures(), decisions_not_kept_,
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
  const bool sample = a.time_scale == causal_twin::SAMPLE_LEVEL;
  if (sample ? !params_.sample_enabled : !params_.condition_enabled) return;
  auto key = std::make_pair(a.asset_group, static_cast<int>(a.time_scale));
  auto it = engines_.find(key);
  if (it == engines_.end()) {
    EngineState st;
    const alarms::AlarmParams p = params_for(sample);
    auto opened = store_.open(a.asset_group, sample, a.channel_names, a.factor_names, p, params_.prognosis);
    st.engine = std::move(opened.engine);  // from the checkpoint if any
    st.trends = std::move(opened.trends);
    if (sample) st.engine->set_id_scope("sample");  // ids unique across time scales
    st.channel_names = a.channel_names;
    st.baseline_logged = st.engine->baseline_ready();
    it = engines_.emplace(key, std::move(st)).first;
    if (opened.resumed) {  // its file appeared after the start (restore_checkpoints publishes the others)
      spdlog::info("asset '{}' {} level: resumed from checkpoint: {} observations, {} active alarms", a.asset_group,
                   sample ? "sample" : "condition", it->second.engine->observations_seen(),
                   it->second.engine->active_alarms().size());
      republish(a.asset_group, a.channel_names, opened.republish);
      republish_prognoses(a.asset_group, it->second, sample);
    } else {
      spdlog::info("asset '{}' {} level: learning the baseline from the first {} observations", a.asset_group,
                   sample ? "sample" : "condition", p.warmup_observations + p.baseline_observations);
    }
  } else if (it->second.unverified) {
    // Restored at start: the stream must be the one the checkpoint was written for (as AlarmStateStore::open).
    const auto& engine = *it->second.engine;
    if (engine.channel_names() != a.channel_names || engine.factor_names() != a.factor_names) {
      throw estimation::StateError("checkpoint '" + store_.path(a.asset_group, sample) +
                               "' was written for other channels or factors than the stream has (did "
                               "causal-estimator restart without its state and learn another causal order?). Move it "
                               "away to start this asset group over");
    }
    it->second.unverified = false;
  }
  EngineState& st = it->second;
  if (store_.is_duplicate(a.asset_group, sample, a.observation.index)) {
    spdlog::debug("asset '{}' {} level: observation {} already processed (re-sent), dropped", a.asset_group,
                  sample ? "sample" : "condition", a.observation.index);
    return;
  }
  if (!sample) {  // the advisor models the condition level only
    advisor_.update(a);
    interventions_.observed(a, advisor_);
  }
  if (!sample && advisor_.has_model(a.asset_group)) {
    const int full = advisor_.full_covariance(a.asset_group) ? 1 : 0;
    if (full != st.full_covariance) {
      st.full_covariance = full;
      spdlog::info("asset '{}': what-if intervals from {}", a.asset_group,
                   full ? "the full per-outcome factor covariance"
                        : "factor standard deviations only (no covariance blocks: correlations ignored)");
    }
  }
  const auto not_running_before = st.engine->not_running_observations();
  const auto gaps_before = st.engine->discontinuities();
  const auto lost_before = st.engine->lost_observations();
  const auto events = st.engine->observe(a.observation);
  if (const auto lost = st.engine->lost_observations() - lost_before; lost > 0) {
    observations_lost_ += lost;
    metrics::process_metrics()
        .counter("recommender_observations_lost_total",
                 "Observations the alarm engines saw skipped by a consecutively numbered source (input lost)",
                 {{"asset_group", a.asset_group}, {"time_scale", sample ? "sample" : "condition"}})
        .inc(static_cast<double>(lost));
  }
  const bool stopped_now = st.engine->not_running_observations() > not_running_before;
  if (!sample) advisor_.set_health(a.asset_group, !st.engine->baseline_ready(), has_open_degradation(*st.engine));
  if (!sample) {  // the trends follow every snapshot, alarm or not, so a prognosis has history at the raise
    const int refused = prognosis::observe_for_prognosis(*st.trends, *st.engine, a.observation,
                                                         a.observation.discontinuity ||
                                                             st.engine->discontinuities() > gaps_before);
    if (refused > 0) {
      spdlog::warn("asset '{}': {} feature values refused by the prognosis trends at observation {} ({} so far)",
                   a.asset_group, refused, a.observation.index, st.trends->refused());
    }
  }
  store_.record(a.asset_group, sample, a.observation.index, events);  // checkpoint before publishing
  for (const auto& e : events) {
    const bool degradation = e.category == alarms::category::kDegradation;
    if (e.state == alarms::AlarmState::Raised && degradation) ++st.raised;
    // Every degradation raise and escalation carries an action, on the alarm and as recommendations at the
    // event's own index (docs/advice.md "From alarm to action"), and the time to the next level (docs/prognosis.md).
    if (degradation && e.state != alarms::AlarmState::Cleared && params_.advice.enabled) {
      const Decision d = decide_for(a, st, e);
      publish_event(a, st, e, d.action);
      recommend(a, e, d);
    } else {
      publish_event(a, st, e, "");
    }
  }
  if (!sample) publish_prognoses(a.asset_group, st, a.observation.index, a.observation.time_ns);
  publish_status(a, stopped_now);
  if (!st.baseline_logged && st.engine->baseline_ready()) {
    st.baseline_logged = true;
    spdlog::info("asset '{}' {} level: baseline learned, monitoring from observation {}", a.asset_group,
                 sample ? "sample" : "condition", a.observation.index);
  }
}

alarms::AlarmParams RecommenderNode::params_for(bool sample_level) const {
  return sample_level ? alarms::AlarmParams::sample_level(params_.sample_baseline_publications) : params_.condition;
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

void RecommenderNode::restore_checkpoints() {
  alarm_message_store_.load_all();  // before the engines: republish() takes each alarm's decision from it
  for (const auto& found : store_.checkpoints()) {
    const bool sample = found.sample_level;
    if (sample ? !params_.sample_enabled : !params_.condition_enabled) continue;
    auto opened = store_.open_checkpoint(found.asset_group, sample, params_for(sample), params_.prognosis);
    EngineState st;
    st.engine = std::move(opened.engine);
    st.trends = std::move(opened.trends);
    if (sample) st.engine->set_id_scope("sample");  // as a new engine: ids unique across time scales
    st.channel_names = st.engine->channel_names();
    st.baseline_logged = st.engine->baseline_ready();
    st.unverified = true;
    spdlog::info("asset '{}' {} level: resumed from checkpoint: {} observations, {} active alarms", found.asset_group,
                 sample ? "sample" : "condition", st.engine->observations_seen(), st.engine->active_alarms().size());
    republish(found.asset_group, st.channel_names, opened.republish);
    const auto placed = engines_.emplace(std::make_pair(found.asset_group, sample ? static_cast<int>(causal_twin::SAMPLE_LEVEL)
                                                                                 : static_cast<int>(causal_twin::CONDITION_LEVEL)),
                                         std::move(st));
    republish_prognoses(found.asset_group, placed.first->second, sample);
  }
  const auto recommendations = recommendation_store_.load_all();
  for (auto r : recommendations) {
    if (recommendations_.write(r, loop_.stop_flag()) == dds::WriteResult::Ok) ++recommendations_published_;
  }
  if (!recommendations.empty()) {
    spdlog::info("{} recommendations re-published from the checkpoint", recommendations.size());
  }
}

void RecommenderNode::republish_prognoses(const std::string& asset_group, const EngineState& st, bool sample) {
  // The prognoses of the last observation processed: the process may have died after the checkpoint and
  // before publishing them (the recorder drops the ones it already has).
  const auto last = store_.last_index(asset_group, sample);
  if (!last || sample || !st.trends) return;
  std::int64_t time_ns = 0;
  for (int k = 0; k < st.trends->channels(); ++k) time_ns = std::max(time_ns, st.trends->trend(k).state().time_ns);
  publish_prognoses(asset_group, st, *last, time_ns);
}

void RecommenderNode::publish_event(const AssembledObservation& a, const EngineState& st, const alarms::AlarmEvent& e,
                                    const std::string& action) {
  dds::to_alarm(a.asset_group, a.channel_names, e, alarm_msg_);
  if (a.time_scale == causal_twin::CONDITION_LEVEL) fill_next_level(st, e, alarm_msg_);
  alarm_msg_.action(action);
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
  spdlog::log(level, "ALARM {} {} [{} {}, root cause {} confidence {:.2f}] {}: {}", alarms::to_string(e.state), e.alarm_id,
              alarms::to_string(e.severity), a.time_scale == causal_twin::SAMPLE_LEVEL ? "sample-level" : "condition-level",
              alarm_msg_.root_cause_name(), e.root_cause_confidence, alarm_msg_.channel_name(), e.reason);
}

}  // namespace causal::recommender

namespace causal::recommender {

void RecommenderNode::fill_next_level(const EngineState& st, const alarms::AlarmEvent& e, causal_twin::Alarm& msg) const {
  prognosis::ChannelPrognosis p;
  if (!params_.prognosis_enabled || !st.trends || !prognosis::next_level_of(*st.trends, *st.engine, e, p)) return;
  set_next_level(p, msg);
  spdlog::info("PROGNOSIS {}: {}", e.alarm_id,
               prognosis_text(msg.channel_name(), p, st.trends->trend(e.channel).state().time_ns,
                              params_.prognosis.coverage));
}

void RecommenderNode::publish_prognoses(const std::string& asset_group, const EngineState& st, std::uint64_t index,
                                        std::int64_t time_ns) {
  if (!params_.prognosis_enabled || !st.trends) return;
  prognosis_metrics_.begin(asset_group);
  for (const auto& p : prognosis::open_alarm_prognoses(*st.trends, *st.engine, index)) {
    to_prognosis(asset_group, st.channel_names, p, index, time_ns, params_.prognosis.coverage, prognosis_msg_);
    if (prognoses_.write(prognosis_msg_, loop_.stop_flag()) == dds::WriteResult::Ok) {
      ++prognoses_published_;
      prognosis_metrics_.on_published(prognosis_msg_);
    } else if (prognosis_write_failures_++ % 100 == 0) {
      spdlog::warn("prognosis for '{}' channel {} not published ({} failures so far)", asset_group, p.channel + 1,
                   prognosis_write_failures_);
    }
    spdlog::debug("PROGNOSIS {}", prognosis_msg_.text());
  }
  prognosis_metrics_.end(asset_group);
}

void RecommenderNode::answer(const causal_twin::WhatIfRequest& request) {
  const auto ans = advisor_.what_if(request.asset_group(), static_cast<int>(request.intervene_channel()) - 1,
                                    request.delta(), request.sustained());
  causal_twin::WhatIfReply reply;
  to_whatif_reply(request, ans, reply);
  if (whatif_replies_.write(reply, loop_.stop_flag()) != dds::WriteResult::Ok) {
    spdlog::error("what-if {}: the reply could not be published (stopping or the writer failed)", request.request_id());
  }
  spdlog::info("what-if {} on '{}': {}", request.request_id(), request.asset_group(), ans.ok ? ans.text : ans.error);
}

}  // namespace causal::recommender
