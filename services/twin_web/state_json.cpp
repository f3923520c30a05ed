// The JSON of /api/state and of the Server-Sent Events: what the page draws, in plain fields. Times are
// milliseconds since the Unix epoch (JavaScript's unit); channels are 1-based as everywhere in the product.
// Every number stored is finite (TwinState refuses the rest), so no NaN can reach the page.
#include "intervention_json.hpp"
#include "twin_state.hpp"

#include "causal/dds/alarm_conversions.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace causal::web {

namespace {

using nlohmann::json;

double ms(std::int64_t ns) { return static_cast<double>(ns) / 1e6; }

// A double that may be non-finite in a message we pass through (scores, intervals): null instead of NaN.
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json trend_json(const GroupState& g) {
  json index = json::array(), time = json::array(), values = json::array();
  for (std::size_t c = 0; c < g.channels.size(); ++c) values.push_back(json::array());
  for (const auto& p : g.trend) {
    index.push_back(p.index);
    time.push_back(ms(p.time_ns));
    for (std::size_t c = 0; c < p.values.size() && c < values.size(); ++c) values[c].push_back(p.values[c]);
  }
  return {{"index", std::move(index)}, {"time_ms", std::move(time)}, {"values", std::move(values)}};
}

json edge_json(const CausalEdge& e) {
  return {{"from", e.from}, {"to", e.to}, {"lag", e.lag}, {"factor", e.factor}, {"std", e.stddev}, {"z", e.z},
          {"significant", std::abs(e.z) >= kSignificantZ}};
}

json graph_json(const GroupState& g) {
  const CausalGraph graph = causal_graph(g);
  json edges = json::array(), self = json::array();
  for (const auto& e : graph.edges) edges.push_back(edge_json(e));
  for (const auto& e : graph.self_lags) self.push_back(edge_json(e));
  std::int64_t newest_ns = 0;
  for (const auto& [k, f] : g.factors) newest_ns = std::max(newest_ns, f.time_ns);
  return {{"index", graph.index},  {"time_ms", ms(newest_ns)}, {"outcomes", g.factors.size()},
          {"min_z", kSignificantZ}, {"edges", std::move(edges)}, {"self_lags", std::move(self)},
          {"unusable", graph.unusable}};
}

// Which model the alarm comes from: the sample-level engine scopes its ids "<group>/sample/..."
// (AlarmEngine::set_id_scope, pinned by tests/dds/test_asset_status.cpp); health alarms are about the twin.
const char* time_scale_of(const causal_twin::Alarm& a) {
  if (a.category() == "health") return "twin";
  return a.alarm_id().rfind(a.asset_group() + "/sample/", 0) == 0 ? "sample" : "condition";
}

json alarm_json(const AlarmView& v) {
  const auto& a = v.last;
  json factors = json::array();
  for (std::size_t i = 0; i < a.factor_names().size(); ++i) {
    factors.push_back({{"name", a.factor_names()[i]},
                       {"baseline", number(i < a.factor_baseline().size() ? a.factor_baseline()[i] : NAN)},
                       {"now", number(i < a.factor_now().size() ? a.factor_now()[i] : NAN)}});
  }
  return {{"id", a.alarm_id()},
          {"channel", a.channel()},
          {"channel_name", a.channel_name()},
          {"severity", dds::to_string(a.severity(), "unknown")},
          {"state", dds::to_string(a.state(), "unknown")},
          {"open", v.open()},
          {"kind", a.kind()},
          {"category", a.category()},
          {"raised_index", v.raised_index},
          {"cleared_index", v.cleared_index ? json(*v.cleared_index) : json(nullptr)},
          {"evidence_index", a.sample_index()},
          {"raised_time_ms", ms(a.raised_time_ns())},
          {"cleared_time_ms", a.cleared_time_ns() != 0 ? json(ms(a.cleared_time_ns())) : json(nullptr)},
          {"root_cause_channel", a.root_cause_channel()},
          {"root_cause_name", a.root_cause_name()},
          {"score", number(a.score())},
          {"threshold", number(a.threshold())},
          {"factors", std::move(factors)},
          {"reason", a.reason()},
          {"time_scale", time_scale_of(a)},
          {"root_cause_confidence", number(a.root_cause_confidence())},
          {"action", a.action()},
          {"next_level", a.next_level()},
          {"hours_to_next_level", number(a.hours_to_next_level())},
          {"hours_to_next_level_low", number(a.hours_to_next_level_low())},
          {"hours_to_next_level_high", number(a.hours_to_next_level_high())},
          {"acknowledged", v.acknowledged},
          {"acknowledged_by", v.acknowledged_by},
          {"shelved", v.shelved},
          {"shelved_until_ms", v.shelved_until_ns != 0 ? json(ms(v.shelved_until_ns)) : json(nullptr)},
          {"shelved_by", v.shelved_by},
          {"shelve_reason", v.shelve_reason},
          {"arrival", v.arrival}};
}

// Time-to-level forecasts of the channels whose alarm is still open (a closed alarm's last forecast is history).
json prognoses_json(const GroupState& g) {
  json out = json::array();
  for (const auto& [key, p] : g.prognoses) {
    const auto alarm = g.alarms.find(p.alarm_id());
    if (alarm == g.alarms.end() || !alarm->second.open()) continue;
    auto eta = [](std::int64_t ns) { return ns != 0 ? json(ms(ns)) : json(nullptr); };
    out.push_back({{"channel", p.channel()},
                   {"channel_name", p.channel_name()},
                   {"level", p.level()},
                   {"alarm_id", p.alarm_id()},
                   {"index", p.sample_index()},
                   {"time_ms", ms(p.time_ns())},
                   {"level_ratio", number(p.level_ratio())},
                   {"current_ratio", number(p.current_ratio())},
                   {"known", p.known()},
                   {"reached", p.reached()},
                   {"hours", number(p.hours())},
                   {"hours_low", number(p.hours_low())},
                   {"hours_high", number(p.hours_high())},
                   {"coverage", number(p.coverage())},
                   {"eta_ms", eta(p.eta_time_ns())},
                   {"eta_low_ms", eta(p.eta_low_time_ns())},
                   {"eta_high_ms", eta(p.eta_high_time_ns())},
                   {"text", p.text()}});
  }
  return out;
}

json recommendation_json(const RecommendationView& v, const GroupState& g) {
  const auto& r = v.last;
  const auto alarm = g.alarms.find(r.alarm_id());
  // Advice without an alarm (on demand) stays current; advice for an alarm is current while the alarm is open.
  const bool current = r.alarm_id().empty() || (alarm != g.alarms.end() && alarm->second.open());
  return {{"id", r.recommendation_id()},
          {"alarm_id", r.alarm_id()},
          {"current", current},
          {"rank", r.rank()},
          {"target_channel", r.target_channel()},
          {"intervene_channel", r.intervene_channel()},
          {"delta", number(r.delta())},
          {"effect_immediate", number(r.effect_immediate())},
          {"effect_steady_state", number(r.effect_steady_state())},
          {"effect_low", number(r.effect_low())},
          {"effect_high", number(r.effect_high())},
          {"confidence", number(r.confidence())},
          {"text", r.text()},
          {"answer_kind", r.answer_kind()},
          {"horizon_snapshots", r.horizon_snapshots()},
          {"spectral_radius", number(r.spectral_radius())},
          {"draws", r.draws()},
          {"unstable_draws", r.unstable_draws()},
          {"unstable_draw_share", number(r.unstable_draw_share())},
          {"effect_median", number(r.effect_median())},
          {"effect_percent", number(r.effect_percent())},
          {"effect_percent_low", number(r.effect_percent_low())},
          {"effect_percent_high", number(r.effect_percent_high())},
          {"effect_level_change", number(r.effect_level_change())},
          {"reliable", r.reliable()},
          {"action_kind", r.action_kind()},
          {"summary", r.summary()},
          {"arrival", v.arrival}};
}

json status_json(const GroupState& g) {
  if (!g.status) return nullptr;
  const auto& s = *g.status;
  return {{"state", s.state()},
          {"text", s.text()},
          {"learning_seen", s.learning_seen()},
          {"learning_needed", s.learning_needed()},
          {"index", s.sample_index()},
          {"time_ms", ms(s.time_ns())},
          {"open_alarms", s.open_alarms()},
          {"has_alarm", s.has_alarm()},
          {"worst_severity", s.has_alarm() ? json(dds::to_string(s.worst_severity(), "unknown")) : json(nullptr)},
          {"root_cause_channel", s.root_cause_channel()},
          {"root_cause_name", s.root_cause_name()},
          {"action", s.action()},
          {"prognosis_text", s.prognosis_text()},
          {"unacknowledged_alarms", s.unacknowledged_alarms()},
          {"shelved_alarms", s.shelved_alarms()},
          {"alarms_per_10_min", s.alarms_per_10_min()},
          {"alarm_flood", s.alarm_flood()},
          {"standing_alarms", s.standing_alarms()},
          {"chattering_alarms", s.chattering_alarms()}};
}

json group_json(const std::string& id, const GroupState& g) {
  json alarms = json::array(), recs = json::array();
  for (const auto& [aid, v] : g.alarms) alarms.push_back(alarm_json(v));
  for (const auto& [rid, v] : g.recommendations) recs.push_back(recommendation_json(v, g));
  json last = nullptr;
  if (!g.trend.empty()) last = {{"index", g.trend.back().index}, {"time_ms", ms(g.trend.back().time_ns)}};
  return {{"id", id},
          {"feature", g.feature},
          {"channels", g.channels},
          {"last", std::move(last)},
          {"missing", g.missing},
          {"trend", trend_json(g)},
          {"graph", graph_json(g)},
          {"alarms", std::move(alarms)},
          {"recommendations", std::move(recs)},
          {"prognoses", prognoses_json(g)},
          {"interventions", interventions_json(g)},
          {"status", status_json(g)}};
}

}  // namespace

std::string group_to_json(const std::string& id, const GroupState& g) {
  return group_json(id, g).dump(-1, ' ', false, json::error_handler_t::replace);
}

// Every group in one line each: enough for the page's group buttons (and to see where alarms are).
std::string overview_to_json(const std::map<std::string, GroupState>& groups,
                             const std::map<std::string, std::string>& info, std::uint64_t version) {
  json list = json::array();
  for (const auto& [id, g] : groups) {
    std::size_t open = 0;
    int worst = -1;
    for (const auto& [aid, a] : g.alarms) {
      if (!a.open()) continue;
      ++open;
      worst = std::max(worst, static_cast<int>(a.last.severity()));
    }
    list.push_back({{"id", id},
                    {"feature", g.feature},
                    {"channels", g.channels},
                    {"has_trend", !g.trend.empty()},
                    {"open_alarms", open},
                    {"state", g.status ? json(g.status->state()) : json(nullptr)},
                    {"status", status_json(g)},
                    {"last_time_ms", g.trend.empty() ? json(nullptr) : json(ms(g.trend.back().time_ns))},
                    {"worst_severity", worst < 0 ? json(nullptr) : json(dds::to_string(static_cast<causal_twin::Severity>(worst), "unknown"))}});
  }
  const json out = {{"version", version}, {"info", info}, {"groups", std::move(list)}};
  return out.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string state_to_json(const std::map<std::string, GroupState>& groups, const StateCounters& c,
                          const std::map<std::string, std::string>& info, std::uint64_t version) {
  json out;
  out["version"] = version;
  out["info"] = info;
  out["counters"] = {{"condition_vectors", c.condition_vectors},
                     {"duplicates", c.duplicates},
                     {"rejected_vectors", c.rejected_vectors},
                     {"trend_points_forgotten", c.trend_points_forgotten},
                     {"snapshots_missing", c.snapshots_missing},
                     {"factor_messages", c.factor_messages},
                     {"factor_messages_skipped", c.factor_messages_skipped},
                     {"factor_messages_rejected", c.factor_messages_rejected},
                     {"alarm_events", c.alarm_events},
                     {"recommendations", c.recommendations},
                     {"statuses", c.statuses},
                     {"prognoses", c.prognoses},
                     {"prognoses_stale", c.prognoses_stale},
                     {"interventions", c.interventions},
                     {"intervention_outcomes", c.intervention_outcomes},
                     {"interventions_forgotten", c.interventions_forgotten}};
  json list = json::array();
  for (const auto& [id, g] : groups) list.push_back(group_json(id, g));
  out["groups"] = std::move(list);
  // Strings from DDS are not guaranteed UTF-8: replace invalid bytes instead of throwing.
  return out.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace causal::web
