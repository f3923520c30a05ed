#include "twin_web_node.hpp"

#include "history_loader.hpp"

#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

namespace causal::web {

TwinWebNode::TwinWebNode(TwinWebOptions options)
    : options_(std::move(options)),
      state_(options_.limits),
      participant_(dds::to_dds_settings(options_.dds, "twin-web")),
      in_(participant_, dds::profiles::kAssetStatusReader),
      replies_in_(participant_, dds::topics::kWhatIfReply, dds::profiles::kWhatIfReader),
      requests_out_(participant_, dds::topics::kWhatIfRequest, dds::profiles::kWhatIfWriter),
      actions_out_(participant_, dds::topics::kAlarmAction, dds::profiles::kAlarmActionWriter),
      interventions_in_(participant_, dds::topics::kIntervention, dds::profiles::kInterventionReader),
      intervention_outcomes_in_(participant_, dds::topics::kInterventionOutcome,
                                dds::profiles::kInterventionOutcomeReader),
      approvals_(participant_),
      inputs_in_(participant_, dds::topics::kConditionInput, dds::profiles::kConditionInputReader) {
  in_.attach_to(loop_);
  loop_.attach(replies_in_.get());
  loop_.attach(interventions_in_.get());
  loop_.attach(intervention_outcomes_in_.get());
  loop_.attach(inputs_in_.get());
  state_.set_info("service", "twin-web");
  state_.set_info("domain", std::to_string(participant_.domain_id()));
  web_ = std::make_unique<WebServer>(options_.web, state_, whatif_, [this] { return whatif_readers_.load(); });
  web_->set_alarm_actions(&actions_);
  web_->set_approvals(&approvals_.bridge(), &source_clock_);
  load_history_at_start();
}

void TwinWebNode::load_history_at_start() {
  if (options_.db_url.empty()) {
    // Said on the page: what a restarted twin-web shows begins here (plus what the topics still replay).
    state_.set_info("data_since", "no history database (--db): data from before twin-web started at " +
                                      io::format_utc_seconds(io::utc_now_ns()) + " is not shown");
    history_routes_ = std::make_unique<HistoryRoutes>(nullptr, 0);
    return;
  }
  history_ = history::open_history(options_.db_url);  // throws HistoryError (a std::runtime_error)
  loaded_ = load_history(*history_, state_, history::RangeQuery{});
  const HistoryLoad& load = loaded_;
  spdlog::info("history {}: {} condition vectors, {} alarm events, {} recommendations, {} prognoses, {} status lines",
               history_->describe(), load.condition_vectors, load.alarm_events, load.recommendations, load.prognoses,
               load.statuses);
  loaded_interventions_ = load_interventions(*history_, state_);
  spdlog::info("history: {} approved interventions, {} intervention outcomes", loaded_interventions_.approvals,
               loaded_interventions_.outcomes);
  if (loaded_interventions_.unreadable > 0) {
    spdlog::warn("history: {} intervention rows could not be read (not shown)", loaded_interventions_.unreadable);
  }
  if (load.unreadable > 0) spdlog::warn("history: {} rows could not be read (not drawn)", load.unreadable);
  state_.set_info("history", history_->describe());
  state_.set_info("data_since", load.earliest_ns ? "history since " + io::format_utc_seconds(*load.earliest_ns)
                                                 : "the history database is empty: data since twin-web started at " +
                                                       io::format_utc_seconds(io::utc_now_ns()));
  history_routes_ = std::make_unique<HistoryRoutes>(history_.get(), options_.limits.trend_points);
  web_->set_history(history_routes_.get());
}

TwinWebNode::~TwinWebNode() {
  whatif_.stop();
  actions_.stop();
  approvals_.stop();
  if (web_) web_->stop();
}

int TwinWebNode::run() {
  web_->start();
  const std::string host = web_->bind_address() == "0.0.0.0" ? "127.0.0.1" : web_->bind_address();
  spdlog::info("twin-web on domain {}: serving {}://{}:{}/", participant_.domain_id(), web_->scheme(), host,
               web_->port());
  if (web_->bind_address() != "127.0.0.1" && web_->bind_address() != "localhost") {
    spdlog::warn("listening on {}: whoever reaches this address can ask the twin what-if questions",
                 web_->bind_address());
  }
  const auto end = loop_.run(
      {options_.idle_exit_s, options_.max_runtime_s},
      [this] {
        send_due_questions();
        send_due_actions();
        approvals_.send_due(loop_.stop_flag());
        return take_available();
      },
      [this] {
        return in_.conditions.matched_writers() + in_.factors.matched_writers() + dds::matched_writers(in_.factor_sets) +
               in_.alarms.matched_writers() + in_.recommendations.matched_writers();
      });
  if (end == dds::RunEnd::Idle) spdlog::info("all publishers gone and no data for {:.1f} s: finishing", options_.idle_exit_s);
  if (end == dds::RunEnd::MaxRuntime) spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
  whatif_.stop();
  actions_.stop();
  approvals_.stop();
  web_->stop();
  StateCounters c = state_.counters();
  // The topic lines count DDS samples: what the history database gave at start is said apart.
  if (history_) {
    spdlog::info("summary history={} condition_vectors={} alarm_events={} recommendations={} prognoses={} statuses={} "
                 "unreadable={}", history_->describe(), loaded_.condition_vectors, loaded_.alarm_events,
                 loaded_.recommendations, loaded_.prognoses, loaded_.statuses, loaded_.unreadable);
  }
  c.condition_vectors -= loaded_.condition_vectors;
  c.alarm_events -= loaded_.alarm_events;
  c.recommendations -= loaded_.recommendations;
  c.prognoses -= loaded_.prognoses;
  c.statuses -= loaded_.statuses;
  c.interventions -= loaded_interventions_.approvals;
  c.intervention_outcomes -= loaded_interventions_.outcomes;
  spdlog::info("summary topic={} received={} duplicates={} refused={} forgotten={} lost={}",
               dds::topics::kConditionVector, c.condition_vectors, c.duplicates, c.rejected_vectors,
               c.trend_points_forgotten, c.snapshots_missing);
  spdlog::info("summary topic={} received={} skipped={} refused={}", dds::topics::kCausalFactors,
               c.factor_messages + c.factor_messages_skipped + c.factor_messages_rejected, c.factor_messages_skipped,
               c.factor_messages_rejected);
  if (factor_set_counts_.received > 0) {  // their batches are counted in the line above
    spdlog::info("summary topic={} received={} batches={} refused={}", dds::topics::kCausalFactorSets,
                 factor_set_counts_.received, factor_set_counts_.batches, factor_set_counts_.refused);
  }
  spdlog::info("summary topic={} received={}", dds::topics::kAlarm, c.alarm_events);
  spdlog::info("summary topic={} received={}", dds::topics::kRecommendation, c.recommendations);
  spdlog::info("summary topic={} received={}", dds::topics::kAssetStatus, c.statuses);
  spdlog::info("summary topic={} received={} stale={}", dds::topics::kPrognosis, c.prognoses, c.prognoses_stale);
  spdlog::info("summary topic={} received={} forgotten={}", dds::topics::kIntervention, c.interventions,
               c.interventions_forgotten);
  spdlog::info("summary topic={} received={}", dds::topics::kInterventionOutcome, c.intervention_outcomes);
  approvals_.log_summary();
  spdlog::info("summary topic={} sent={} failed={} asked={} answered={}", dds::topics::kWhatIfRequest, requests_sent_,
               requests_failed_, whatif_.asked(), whatif_.answered());
  spdlog::info("summary topic={} sent={} failed={} asked={} answered={}", dds::topics::kAlarmAction, actions_sent_,
               actions_failed_, actions_.asked(), actions_.answered());
  const auto refused = in_.conditions.rejections().total() + in_.factors.rejections().total() +
                       (in_.factor_sets ? in_.factor_sets->rejections().total() : 0) +
                       in_.alarms.rejections().total() + in_.recommendations.rejections().total() +
                       in_.status.rejections().total() + in_.prognoses.rejections().total();
  if (refused > 0) spdlog::warn("DDS readers refused {} samples (resource limits)", refused);
  return 0;
}

std::size_t TwinWebNode::take_available() {
  std::size_t n = 0;
  n += in_.conditions.take_all([this](const auto& c, const auto&) { state_.on_condition(c); }, loop_.stop_flag());
  // Gaps in the trends (snapshot indices skipped, input lost upstream): twin_web_snapshots_missing.
  missing_metric_->set(static_cast<double>(state_.counters().snapshots_missing));
  n += in_.factors.take_all([this](const auto& f, const auto&) { state_.on_factors(f); }, loop_.stop_flag());
  // One message per input (estimator.yaml output.factor_messages set): its batches, in order, as if one by one.
  n += dds::take_factor_sets(
      in_.factor_sets, factor_set_counts_, [this](const auto& f, const auto&) { state_.on_factors(f); },
      [](const auto& set, const std::string& problem) {
        spdlog::warn("causal factor set of '{}' refused: {}", set.asset_group(), problem);
      },
      &loop_.stop_flag());
  n += in_.alarms.take_all([this](const auto& a, const auto&) { state_.on_alarm(a); }, loop_.stop_flag());
  n += in_.status.take_all([this](const auto& st, const auto&) { state_.on_status(st); }, loop_.stop_flag());
  n += in_.prognoses.take_all([this](const auto& p, const auto&) { state_.on_prognosis(p); }, loop_.stop_flag());
  n += in_.recommendations.take_all([this](const auto& r, const auto&) { state_.on_recommendation(r); },
                                    loop_.stop_flag());
  n += in_.action_results.take_all(
      [this](const auto& r, const auto&) {
        state_.on_action_result(r);
        actions_.on_reply(r);
      },
      loop_.stop_flag());
  n += interventions_in_.take_all(
      [this](const auto& i, const auto& info) {
        if (approvals_.on_read(i, info.sample_identity.writer_guid())) state_.on_intervention(i);
      },
      loop_.stop_flag());
  n += inputs_in_.take_all([this](const auto& c, const auto&) {
    source_clock_.on_input(c.asset_group(), c.snapshot_index(), c.time_ns());
  }, loop_.stop_flag());
  n += intervention_outcomes_in_.take_all([this](const auto& o, const auto&) { state_.on_intervention_outcome(o); },
                                          loop_.stop_flag());
  n += replies_in_.take_all(
      [this](const auto& r, const auto&) {
        ++replies_received_;
        whatif_.on_reply(r);
      },
      loop_.stop_flag());
  return n;
}

void TwinWebNode::send_due_questions() {
  whatif_readers_.store(requests_out_.matched_readers());
  if (whatif_readers_.load() == 0) return;  // nobody to ask yet: the asker's timeout decides
  for (auto& request : whatif_.due(WhatIfBridge::Clock::now())) {
    // Never block the DDS thread for long: a request that cannot go out now is retried a second later.
    if (requests_out_.write(request, loop_.stop_flag(), std::chrono::milliseconds(200)) == dds::WriteResult::Ok) {
      ++requests_sent_;
    } else {
      ++requests_failed_;
    }
  }
}

void TwinWebNode::send_due_actions() {
  if (actions_out_.matched_readers() == 0) return;  // no alarm-recommender yet: the page's timeout decides
  for (auto& action : actions_.due(AlarmActionBridge::Clock::now())) {
    if (actions_out_.write(action, loop_.stop_flag(), std::chrono::milliseconds(200)) == dds::WriteResult::Ok) {
      ++actions_sent_;
    } else {
      ++actions_failed_;
    }
  }
}

}  // namespace causal::web
