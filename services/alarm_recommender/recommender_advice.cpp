// alarm-recommender: the action published with every degradation alarm event (advice_policy.hpp decides).
#include "recommender_node.hpp"

#include "advice_conversions.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

namespace causal::recommender {

Decision RecommenderNode::decide_for(const AssembledObservation& a, const EngineState& st,
                                     const alarms::AlarmEvent& e) const {
  AlarmSituation s;
  s.asset_group = a.asset_group;
  s.channel_names = st.channel_names;
  s.target = e.channel;
  s.severity = e.severity;
  s.root_cause = e.root_cause_channel;
  s.open_alarms = st.engine->active_alarms();
  s.time_ns = a.observation.time_ns;
  std::vector<AdviceItem> candidates;
  std::string why;
  const bool sample = a.time_scale == causal_twin::SAMPLE_LEVEL;
  if (sample) {
    why = "a sample-level alarm: levers are judged on the condition-level model";
  } else {
    s.snapshot_hours = advisor_.snapshot_hours(a.asset_group);
    // Baseline of each channel's raw feature, from the engine's healthy baseline (log units when it logs).
    const int g = static_cast<int>(st.channel_names.size());
    Eigen::VectorXd baseline(g);
    for (int j = 0; j < g; ++j) {
      const auto d = st.engine->channel_diagnostics(j).feature;
      baseline[j] = !d.monitored                                ? NAN
                    : st.engine->params().feature_log_transform ? std::exp(d.baseline_location)
                                                                : d.baseline_location;
    }
    candidates = advisor_.evaluate(a.asset_group, e.channel, baseline, why);
  }
  const auto trust = order_trust_.find(a.asset_group);
  return decide(s, candidates, why, trust == order_trust_.end() ? OrderTrust{} : trust->second, params_.actions,
                params_.policy);
}

void RecommenderNode::recommend(const AssembledObservation& a, const alarms::AlarmEvent& e, const Decision& d) {
  ++events_advised_;
  ++(d.kind == "upstream_lever" ? events_upstream_lever_ : events_act_on_asset_);
  const auto it = order_trust_.find(a.asset_group);
  OrderTrust trust = it == order_trust_.end() ? OrderTrust{} : it->second;
  std::string why_not;
  if (!order_trusted(trust, params_.policy, why_not)) trust.source = "untrusted";
  const double snapshot_hours =
      a.time_scale == causal_twin::CONDITION_LEVEL ? advisor_.snapshot_hours(a.asset_group) : NAN;
  RecommendationContext ctx;
  ctx.asset_group = a.asset_group;
  ctx.alarm_id = e.alarm_id;
  ctx.sample_index = e.index;
  // A raise keeps the id "<alarm_id>/<rank>"; each escalation gets its own instance, so none replaces another.
  ctx.id_prefix = e.state == alarms::AlarmState::Raised ? e.alarm_id : e.alarm_id + "@" + std::to_string(e.index);
  ctx.action_kind = d.kind;
  ctx.act_on_channel = d.act_on;
  ctx.act_on_name = a.channel_names.at(static_cast<std::size_t>(d.act_on));
  ctx.order_confidence = trust.confidence;
  ctx.order_source = trust.source;
  causal_twin::Recommendation msg;
  for (const auto& item : d.items) {
    if (item.rank > params_.advice.max_per_alarm) break;
    ctx.action = item.action;
    ctx.horizon_hours = item.diag.kind == "horizon" ? item.diag.horizon_snapshots * snapshot_hours : NAN;
    to_recommendation(ctx, item, msg);
    withdraw_if_untrusted(interventions_, msg);  // a lever whose intervention outcomes missed is not claimed
    recommendation_store_.record(msg);  // kept before it is published, as the alarm events
    if (recommendations_.write(msg, loop_.stop_flag()) == dds::WriteResult::Ok) ++recommendations_published_;
    spdlog::info("RECOMMENDATION {} at {} #{} [{}, act on {}]: {}", e.alarm_id, e.index, item.rank, d.kind,
                 ctx.act_on_name, item.text);
  }
  status_.note_action(e.alarm_id, d.action);  // the operator's status line shows the latest action
}

}  // namespace causal::recommender
