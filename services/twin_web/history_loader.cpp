#include "history_loader.hpp"

#include "history_cells.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/history/json_cells.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace causal::web {

namespace {

using history::Row;

// The enum value whose name (dds::to_string) is `name`; the IDL enums have 3 values each.
template <typename E>
E enum_named(const std::string& name) {
  for (int i = 0; i < 3; ++i) {
    if (name == dds::to_string(static_cast<E>(i), "?")) return static_cast<E>(i);
  }
  throw std::invalid_argument("unknown value " + name);
}

causal_twin::ConditionVector make_condition(const Row& row) {
  const HistoryCells c("condition_vectors", row);
  causal_twin::ConditionVector v;
  v.asset_group(c.text("asset_group"));
  v.feature(c.text("feature"));
  v.snapshot_index(static_cast<std::uint64_t>(c.integer("snapshot")));
  v.time_ns(c.integer("time_ns"));
  const auto names = history::parse_json_string_array(c.text("channel_names"));
  const auto values = history::parse_json_number_array(c.text("channel_values"));
  if (!names || !values || names->size() != values->size()) throw std::invalid_argument("channel arrays");
  v.channel_names(*names);
  std::vector<double> x;
  for (const auto& value : *values) x.push_back(value.value_or(NAN));  // NaN: refused and counted by TwinState
  v.values(x);
  return v;
}

causal_twin::Alarm make_alarm(const Row& row) {
  const HistoryCells c("alarms", row);
  causal_twin::Alarm a;
  a.alarm_id(c.text("alarm_id"));
  a.state(enum_named<causal_twin::AlarmState>(c.text("state")));
  a.severity(enum_named<causal_twin::Severity>(c.text("severity")));
  a.kind(c.text("kind"));
  a.asset_group(c.text("asset_group"));
  a.channel(static_cast<std::uint16_t>(c.integer("channel")));
  a.channel_name(c.text("channel_name"));
  a.sample_index(static_cast<std::uint64_t>(c.integer("sample_index")));
  a.raised_time_ns(c.utc("raised_utc"));
  a.cleared_time_ns(c.utc("cleared_utc"));
  a.root_cause_channel(static_cast<std::uint16_t>(c.integer("root_cause_channel")));
  a.root_cause_name(c.text("root_cause_name"));
  a.score(c.real("score"));
  a.threshold(c.real("threshold"));
  a.reason(c.text("reason"));
  a.category(c.text("category"));
  a.root_cause_confidence(c.real("root_cause_confidence"));
  a.next_level(c.text("next_level"));
  a.hours_to_next_level(c.real("hours_to_next_level"));
  a.hours_to_next_level_low(c.real("hours_to_next_level_low"));
  a.hours_to_next_level_high(c.real("hours_to_next_level_high"));
  return a;
}

causal_twin::Recommendation make_recommendation(const Row& row) {
  const HistoryCells c("recommendations", row);
  causal_twin::Recommendation r;
  r.recommendation_id(c.text("recommendation_id"));
  r.alarm_id(c.text("alarm_id"));
  r.asset_group(c.text("asset_group"));
  r.rank(static_cast<std::uint16_t>(c.integer("rank")));
  r.target_channel(static_cast<std::uint16_t>(c.integer("target_channel")));
  r.intervene_channel(static_cast<std::uint16_t>(c.integer("intervene_channel")));
  r.delta(c.real("delta"));
  r.effect_immediate(c.real("effect_immediate"));
  r.effect_steady_state(c.real("effect_steady_state"));
  r.effect_low(c.real("effect_low"));
  r.effect_high(c.real("effect_high"));
  r.confidence(c.real("confidence"));
  r.text(c.text("text"));
  r.answer_kind(c.text("answer_kind"));
  r.horizon_snapshots(static_cast<std::uint16_t>(c.integer("horizon_snapshots")));
  r.spectral_radius(c.real("spectral_radius"));
  r.draws(static_cast<std::uint32_t>(c.integer("draws")));
  r.unstable_draws(static_cast<std::uint32_t>(c.integer("unstable_draws")));
  r.unstable_draw_share(c.real("unstable_draw_share"));
  r.effect_median(c.real("effect_median"));
  r.effect_percent(c.real("effect_percent"));
  r.effect_percent_low(c.real("effect_percent_low"));
  r.effect_percent_high(c.real("effect_percent_high"));
  r.effect_level_change(c.real("effect_level_change"));
  r.reliable(c.boolean("reliable"));
  r.summary(c.text("summary"));
  r.sample_index(static_cast<std::uint64_t>(c.integer("sample_index")));
  r.action(c.text("action"));
  r.action_kind(c.text("action_kind"));
  r.act_on_channel(static_cast<std::uint16_t>(c.integer("act_on_channel")));
  r.act_on_name(c.text("act_on_name"));
  r.horizon_hours(c.real("horizon_hours"));
  r.order_confidence(c.real("order_confidence"));
  r.order_source(c.text("order_source"));
  return r;
}

causal_twin::Prognosis make_prognosis(const Row& row) {
  const HistoryCells c("prognoses", row);
  causal_twin::Prognosis p;
  p.asset_group(c.text("asset_group"));
  p.channel(static_cast<std::uint16_t>(c.integer("channel")));
  p.channel_name(c.text("channel_name"));
  p.sample_index(static_cast<std::uint64_t>(c.integer("sample_index")));
  p.time_ns(c.utc("time_utc"));
  p.level(c.text("level"));
  p.hours(c.real("hours"));
  p.hours_low(c.real("hours_low"));
  p.hours_high(c.real("hours_high"));
  p.known(c.boolean("known"));
  p.reached(c.boolean("reached"));
  p.level_ratio(c.real("level_ratio"));
  p.current_ratio(c.real("current_ratio"));
  p.growth_per_hour(c.real("growth_per_hour"));
  p.coverage(c.real("coverage"));
  p.eta_time_ns(c.utc("eta_utc"));
  p.eta_low_time_ns(c.utc("eta_low_utc"));
  p.eta_high_time_ns(c.utc("eta_high_utc"));
  p.alarm_id(c.text("alarm_id"));
  p.text(c.text("text"));
  return p;
}

causal_twin::AssetStatus make_status(const Row& row) {
  const HistoryCells c("asset_status", row);
  causal_twin::AssetStatus s;
  s.asset_group(c.text("asset_group"));
  s.state(c.text("state"));
  s.learning_seen(static_cast<std::uint32_t>(c.integer("learning_seen")));
  s.learning_needed(static_cast<std::uint32_t>(c.integer("learning_needed")));
  s.sample_index(static_cast<std::uint64_t>(c.integer("sample_index")));
  s.time_ns(c.utc("time_utc"));
  s.has_alarm(c.boolean("has_alarm"));
  if (s.has_alarm()) s.worst_severity(enum_named<causal_twin::Severity>(c.text("worst_severity")));
  s.open_alarms(static_cast<std::uint16_t>(c.integer("open_alarms")));
  s.root_cause_channel(static_cast<std::uint16_t>(c.integer("root_cause_channel")));
  s.root_cause_name(c.text("root_cause_name"));
  s.action(c.text("action"));
  s.prognosis_text(c.text("prognosis_text"));
  s.text(c.text("text"));
  s.unacknowledged_alarms(static_cast<std::uint16_t>(c.integer("unacknowledged_alarms")));
  s.shelved_alarms(static_cast<std::uint16_t>(c.integer("shelved_alarms")));
  s.alarms_per_10_min(static_cast<std::uint16_t>(c.integer("alarms_per_10_min")));
  s.alarm_flood(c.boolean("alarm_flood"));
  s.standing_alarms(static_cast<std::uint16_t>(c.integer("standing_alarms")));
  s.chattering_alarms(static_cast<std::uint16_t>(c.integer("chattering_alarms")));
  return s;
}

template <typename T, typename Key>
void sort_by(std::vector<T>& v, Key key) {
  std::stable_sort(v.begin(), v.end(), [&](const T& a, const T& b) { return key(a) < key(b); });
}

}  // namespace

std::optional<causal_twin::ConditionVector> condition_from_row(const Row& row) { return guarded(make_condition, row); }
std::optional<causal_twin::Alarm> alarm_from_row(const Row& row) { return guarded(make_alarm, row); }
std::optional<causal_twin::Recommendation> recommendation_from_row(const Row& row) {
  return guarded(make_recommendation, row);
}
std::optional<causal_twin::Prognosis> prognosis_from_row(const Row& row) { return guarded(make_prognosis, row); }
std::optional<causal_twin::AssetStatus> status_from_row(const Row& row) { return guarded(make_status, row); }

HistoryLoad load_history(history::HistoryStore& store, TwinState& state, const history::RangeQuery& range) {
  HistoryLoad out;
  auto rows = [&](const char* name) { return store.select(history::table(name), range); };
  for (const auto& v : readable(rows("condition_vectors"), condition_from_row, out.unreadable)) {
    if (!out.earliest_ns || v.time_ns() < *out.earliest_ns) out.earliest_ns = v.time_ns();
    state.on_condition(v);
    ++out.condition_vectors;
  }
  // Alarm events in the order they happened: by evidence index, and within one index raise, escalation, clear
  // (an escalation's time can be unknown, so the time column alone does not order them).
  auto alarms = readable(rows("alarms"), alarm_from_row, out.unreadable);
  sort_by(alarms, [](const causal_twin::Alarm& a) { return std::make_pair(a.sample_index(), static_cast<int>(a.state())); });
  for (const auto& a : alarms) state.on_alarm(a);
  out.alarm_events = alarms.size();
  for (const auto& x : readable(rows("recommendations"), recommendation_from_row, out.unreadable)) {
    state.on_recommendation(x);
    ++out.recommendations;
  }
  auto prognoses = readable(rows("prognoses"), prognosis_from_row, out.unreadable);
  sort_by(prognoses, [](const causal_twin::Prognosis& p) { return p.sample_index(); });
  for (const auto& p : prognoses) state.on_prognosis(p);
  out.prognoses = prognoses.size();
  auto statuses = readable(rows("asset_status"), status_from_row, out.unreadable);
  sort_by(statuses, [](const causal_twin::AssetStatus& st) { return st.sample_index(); });
  for (const auto& st : statuses) state.on_status(st);
  out.statuses = statuses.size();
  return out;
}

}  // namespace causal::web
