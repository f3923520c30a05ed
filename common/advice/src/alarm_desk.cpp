// AlarmDesk: the streams' engines (opened, restored, verified), the order of one observation's judgement, and what
// goes out with it: the decision and next level of every event, the prognoses of the open alarms, the status facts,
// and the intervention outcome checks that finished.
#include "causal/advice/alarm_desk.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/prognosis/prognosis_text.hpp"

#include <algorithm>
#include <cmath>

namespace causal::advice {

namespace {

bool has_open_degradation(const alarms::AlarmEngine& engine) {
  for (const auto& e : engine.active_alarms()) {
    if (e.category == alarms::category::kDegradation) return true;
  }
  return false;
}


// The Alarm message's channel name (empty when the names do not reach the channel): the PROGNOSIS text names the
// channel as the alarm does.
std::string alarm_channel_name(const std::vector<std::string>& names, int channel) {
  return channel >= 0 && static_cast<std::size_t>(channel) < names.size() ? names[static_cast<std::size_t>(channel)]
                                                                          : std::string();
}

}  // namespace

AlarmDesk::AlarmDesk(RecommenderParams params, std::string state_dir)
    : params_(std::move(params)), advisor_(params_.advice), store_(std::move(state_dir)) {}

alarms::AlarmParams AlarmDesk::params_for(bool sample_level) const {
  return sample_level ? alarms::AlarmParams::sample_level(params_.sample_baseline_publications) : params_.condition;
}

std::vector<Resumed> AlarmDesk::restore() {
  std::vector<Resumed> out;
  for (const auto& found : store_.checkpoints()) {
    const bool sample = found.sample_level;
    if (!enabled(sample ? TimeScale::Sample : TimeScale::Condition)) continue;
    auto opened = store_.open_checkpoint(found.asset_group, sample, params_for(sample), params_.prognosis);
    EngineState st;
    st.engine = std::move(opened.engine);
    st.trends = std::move(opened.trends);
    if (sample) st.engine->set_id_scope("sample");  // as a new engine: ids unique across time scales
    st.channel_names = st.engine->channel_names();
    st.baseline_logged = st.engine->baseline_ready();
    st.unverified = true;
    const auto placed = engines_.emplace(
        Key{found.asset_group, static_cast<int>(sample ? TimeScale::Sample : TimeScale::Condition)}, std::move(st));
    Resumed r;
    r.republish = std::move(opened.republish);
    restored(found.asset_group, sample, placed.first->second, r);
    out.push_back(std::move(r));
  }
  return out;
}

void AlarmDesk::restored(const std::string& asset_group, bool sample, const EngineState& st, Resumed& out) const {
  out.asset_group = asset_group;
  out.time_scale = sample ? TimeScale::Sample : TimeScale::Condition;
  out.channel_names = st.channel_names;
  out.observations = st.engine->observations_seen();
  out.active_alarms = st.engine->active_alarms().size();
  // The prognoses of the last observation processed: the process may have died after the checkpoint and before
  // publishing them (the recorder drops the ones it already has).
  const auto last = store_.last_index(asset_group, sample);
  if (!last || sample || !st.trends || !params_.prognosis_enabled) return;
  std::int64_t time_ns = 0;
  for (int k = 0; k < st.trends->channels(); ++k) time_ns = std::max(time_ns, st.trends->trend(k).state().time_ns);
  out.prognoses_judged = true;
  out.prognoses = prognoses(st, *last, time_ns);
}

AlarmDesk::EngineState& AlarmDesk::engine_for(const JudgedInput& input, Judgement& out) {
  const bool sample = input.time_scale == TimeScale::Sample;
  const Key key{input.asset_group, static_cast<int>(input.time_scale)};
  auto it = engines_.find(key);
  if (it == engines_.end()) {
    EngineState st;
    const alarms::AlarmParams p = params_for(sample);
    auto opened = store_.open(input.asset_group, sample, input.channel_names, input.factor_names, p, params_.prognosis);
    st.engine = std::move(opened.engine);  // from the checkpoint if any
    st.trends = std::move(opened.trends);
    if (sample) st.engine->set_id_scope("sample");  // ids unique across time scales
    st.channel_names = input.channel_names;
    st.baseline_logged = st.engine->baseline_ready();
    it = engines_.emplace(key, std::move(st)).first;
    out.opened = true;
    out.resumed = opened.resumed;  // its file appeared after the start (restore() gave the others)
    if (opened.resumed) {
      out.resumed_from.republish = std::move(opened.republish);
      restored(input.asset_group, sample, it->second, out.resumed_from);
    } else {
      out.learning_observations = p.warmup_observations + p.baseline_observations;
    }
  } else if (it->second.unverified) {
    // Restored at start: the stream must be the one the checkpoint was written for (as AlarmStateStore::open).
    const auto& engine = *it->second.engine;
    if (engine.channel_names() != input.channel_names || engine.factor_names() != input.factor_names) {
      throw estimation::StateError("checkpoint '" + store_.path(input.asset_group, sample) +
                                   "' was written for other channels or factors than the stream has (did "
                                   "causal-estimator restart without its state and learn another causal order?). "
                                   "Move it away to start this asset group over");
    }
    it->second.unverified = false;
  }
  return it->second;
}

void AlarmDesk::model_step(const JudgedInput& input, EngineState& st, Judgement& out) {
  advisor_.update(input);  // the advisor models the condition level only
  out.finished_outcomes = check_outcomes(input);
  if (!advisor_.has_model(input.asset_group)) return;
  const int full = advisor_.full_covariance(input.asset_group) ? 1 : 0;
  if (full != st.full_covariance) {
    st.full_covariance = full;
    out.covariance_changed = true;
    out.full_covariance = full == 1;
  }
}

Judgement AlarmDesk::judge(const JudgedInput& input) {
  Judgement out;
  if (!enabled(input.time_scale)) return out;
  const bool sample = input.time_scale == TimeScale::Sample;
  EngineState& st = engine_for(input, out);
  if (store_.is_duplicate(input.asset_group, sample, input.observation.index)) {
    out.duplicate = true;
    return out;
  }
  out.judged = true;
  if (!sample) model_step(input, st, out);
  const auto not_running_before = st.engine->not_running_observations();
  const auto gaps_before = st.engine->discontinuities();
  const auto lost_before = st.engine->lost_observations();
  const auto events = st.engine->observe(input.observation);
  out.observations_lost = st.engine->lost_observations() - lost_before;
  const bool stopped_now = st.engine->not_running_observations() > not_running_before;
  if (!sample) {
    advisor_.set_health(input.asset_group, !st.engine->baseline_ready(), has_open_degradation(*st.engine));
    // The trends follow every snapshot, alarm or not, so a prognosis has history at the raise.
    out.trend_values_refused = prognosis::observe_for_prognosis(
        *st.trends, *st.engine, input.observation,
        input.observation.discontinuity || st.engine->discontinuities() > gaps_before);
    out.trend_values_refused_total = st.trends->refused();
  }
  store_.record(input.asset_group, sample, input.observation.index, events);  // checkpoint before publishing
  out.checkpoint_errors = store_.take_errors();
  for (const auto& e : events) judge_event(input, st, e, out);
  if (!sample && params_.prognosis_enabled && st.trends) {
    out.prognoses_judged = true;
    out.prognoses = prognoses(st, input.observation.index, input.observation.time_ns);
  }
  out.status = status_facts(input, stopped_now);
  if (!st.baseline_logged && st.engine->baseline_ready()) {
    st.baseline_logged = true;
    out.baseline_learned = true;
  }
  return out;
}

std::vector<EngineSummary> AlarmDesk::summaries() const {
  std::vector<EngineSummary> out;
  for (const auto& [key, st] : engines_) {
    EngineSummary s;
    s.asset_group = key.first;
    s.time_scale = static_cast<TimeScale>(key.second);
    s.observations = st.engine->observations_seen();
    s.raised = st.raised;
    s.active = st.engine->active_alarms().size();
    s.discontinuities = st.engine->discontinuities();
    s.operating_changes = st.engine->operating_changes();
    out.push_back(std::move(s));
  }
  return out;
}

void AlarmDesk::judge_event(const JudgedInput& input, EngineState& st, const alarms::AlarmEvent& e,
                            Judgement& out) {
  EventJudgement j;
  j.event = e;
  const bool degradation = e.category == alarms::category::kDegradation;
  const bool condition = input.time_scale == TimeScale::Condition;
  if (e.state == alarms::AlarmState::Raised && degradation) ++st.raised;
  // Every degradation raise and escalation carries an action, on the alarm and as recommendations at the event's
  // own index (docs/advice.md "From alarm to action"), and the time to the next level (docs/prognosis.md).
  if (degradation && e.state != alarms::AlarmState::Cleared && params_.advice.enabled) {
    j.advised = true;
    j.decision = decide_for(input, st, e);
    const auto it = order_trust_.find(input.asset_group);
    j.trust = it == order_trust_.end() ? OrderTrust{} : it->second;
    std::string why_not;
    if (!order_trusted(j.trust, params_.policy, why_not)) j.trust.source = "untrusted";
    j.snapshot_hours = condition ? advisor_.snapshot_hours(input.asset_group) : NAN;
  }
  if (condition && params_.prognosis_enabled && st.trends &&
      prognosis::next_level_of(*st.trends, *st.engine, e, j.next_level)) {
    j.has_next_level = true;
    j.next_level_text = prognosis::prognosis_text(alarm_channel_name(input.channel_names, e.channel), j.next_level,
                                                  st.trends->trend(e.channel).state().time_ns,
                                                  params_.prognosis.coverage);
  }
  out.events.push_back(std::move(j));
}

Decision AlarmDesk::decide_for(const JudgedInput& input, const EngineState& st, const alarms::AlarmEvent& e) const {
  AlarmSituation s;
  s.asset_group = input.asset_group;
  s.channel_names = st.channel_names;
  s.target = e.channel;
  s.severity = e.severity;
  s.root_cause = e.root_cause_channel;
  s.open_alarms = st.engine->active_alarms();
  s.time_ns = input.observation.time_ns;
  std::vector<AdviceItem> candidates;
  std::string why;
  if (input.time_scale == TimeScale::Sample) {
    why = "a sample-level alarm: levers are judged on the condition-level model";
  } else {
    s.snapshot_hours = advisor_.snapshot_hours(input.asset_group);
    // Baseline of each channel's raw feature, from the engine's healthy baseline (log units when it logs).
    const int g = static_cast<int>(st.channel_names.size());
    Eigen::VectorXd baseline(g);
    for (int j = 0; j < g; ++j) {
      const auto d = st.engine->channel_diagnostics(j).feature;
      baseline[j] = !d.monitored                                ? NAN
                    : st.engine->params().feature_log_transform ? std::exp(d.baseline_location)
                                                                : d.baseline_location;
    }
    candidates = advisor_.evaluate(input.asset_group, e.channel, baseline, why);
  }
  const auto trust = order_trust_.find(input.asset_group);
  return decide(s, candidates, why, trust == order_trust_.end() ? OrderTrust{} : trust->second, params_.actions,
                params_.policy);
}

std::vector<PrognosisLine> AlarmDesk::prognoses(const EngineState& st, std::uint64_t index, std::int64_t time_ns) const {
  std::vector<PrognosisLine> out;
  for (auto& p : prognosis::open_alarm_prognoses(*st.trends, *st.engine, index)) {
    PrognosisLine line;
    line.channel_name = prognosis::channel_label(st.channel_names, p.channel);
    line.text = prognosis::prognosis_text(line.channel_name, p, time_ns, params_.prognosis.coverage);
    line.index = index;
    line.time_ns = time_ns;
    line.prognosis = std::move(p);
    out.push_back(std::move(line));
  }
  return out;
}

std::string AlarmDesk::status_prognosis(const EngineState& st, const alarms::AlarmEvent& worst) const {
  if (!params_.prognosis_enabled || !st.trends) return "";
  // The root cause's own condition-level alarm when it has one (the asset to act on), else the worst alarm's
  // channel; the prognosis trends follow the condition level only.
  const int channel = worst.root_cause_channel >= 0 ? worst.root_cause_channel : worst.channel;
  const alarms::AlarmEvent* chosen = nullptr;
  const auto active = st.engine->active_alarms();
  for (const auto& e : active) {
    if (e.category != alarms::category::kDegradation || e.channel != channel) continue;
    if (chosen == nullptr || e.severity > chosen->severity) chosen = &e;
  }
  if (chosen == nullptr) {
    for (const auto& e : active) {
      if (e.alarm_id == worst.alarm_id) chosen = &e;
    }
  }
  prognosis::ChannelPrognosis p;
  if (chosen == nullptr || !prognosis::next_level_of(*st.trends, *st.engine, *chosen, p)) return "unknown";
  return prognosis::status_prognosis_text(prognosis::channel_label(st.channel_names, p.channel), p,
                                          st.trends->trend(p.channel).state().time_ns);
}

StatusFacts AlarmDesk::status_facts(const JudgedInput& input, bool stopped_now) {
  StatusFacts f;
  const auto condition = engines_.find({input.asset_group, static_cast<int>(TimeScale::Condition)});
  const auto sample = engines_.find({input.asset_group, static_cast<int>(TimeScale::Sample)});
  f.condition = condition != engines_.end() ? condition->second.engine.get() : nullptr;
  f.sample = sample != engines_.end() ? sample->second.engine.get() : nullptr;
  // The operating state and the learning count come from the condition level when it runs (one observation per
  // snapshot); the sample level speaks for them only when it runs alone.
  if (input.time_scale == TimeScale::Sample && f.condition != nullptr) {
    f.stopped_now = status_last_stopped_[input.asset_group];
  } else {
    f.stopped_now = stopped_now;
    status_last_stopped_[input.asset_group] = stopped_now;
  }
  f.index = input.observation.index;
  f.time_ns = input.observation.time_ns;
  if (condition != engines_.end()) {
    const EngineState& st = condition->second;  // a map node: stays where it is while the desk lives
    f.prognosis = [this, &st](const alarms::AlarmEvent& worst) { return status_prognosis(st, worst); };
  }
  return f;
}

std::vector<intervention::Outcome> AlarmDesk::check_outcomes(const JudgedInput& input) {
  std::vector<intervention::Outcome> done;
  if (input.time_scale != TimeScale::Condition || input.observation.features.size() == 0) return done;
  const std::uint64_t n = input.observation.index;
  // The outcome check works in log levels (the model's units when the estimator logs its features).
  Eigen::VectorXd z = input.observation.features;
  if (params_.advice.model_log_features) z = z.array().max(0.0).log().matrix();  // 0 gives -inf: rejected, counted
  check_.observe(input.asset_group, n, z, done);
  for (const auto& plan : check_.due(input.asset_group, n)) check_.freeze(plan.request_id, predict(plan), done);
  return done;
}

// The what-if the approval is checked against, from the advisor's model as of the snapshot before the start.
intervention::Prediction AlarmDesk::predict(const intervention::InterventionPlan& plan) const {
  intervention::Prediction p;
  const WhatIfAnswer a = advisor_.what_if(plan.asset_group, plan.lever, plan.delta, true);
  const auto k = static_cast<Eigen::Index>(plan.target);
  if (!a.ok || k >= a.effect.size()) {
    p.why = a.ok ? "target channel outside the group" : a.error;
    return p;
  }
  p.ok = std::isfinite(a.effect[k]) && std::isfinite(a.lower[k]) && std::isfinite(a.upper[k]);
  if (!p.ok) p.why = "no finite effect predicted";
  p.steady_state = a.diag.kind == "steady_state";
  p.horizon = a.diag.horizon_snapshots;
  p.effect = a.effect[k];
  p.low = a.lower[k];
  p.high = a.upper[k];
  return p;
}


}  // namespace causal::advice
