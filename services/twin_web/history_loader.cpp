#include "history_loader.hpp"

#include "history_cells.hpp"

#include "causal/history/json_cells.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace causal::web {

namespace {

using history::Row;

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

template <typename T, typename Key>
void sort_by(std::vector<T>& v, Key key) {
  std::stable_sort(v.begin(), v.end(), [&](const T& a, const T& b) { return key(a) < key(b); });
}

}  // namespace

std::optional<causal_twin::ConditionVector> condition_from_row(const Row& row) { return guarded(make_condition, row); }
// The other tables: back into messages through the lists causal-recorder wrote them with.
std::optional<causal_twin::Alarm> alarm_from_row(const Row& row) { return message_from_row<causal_twin::Alarm>(row); }
std::optional<causal_twin::Recommendation> recommendation_from_row(const Row& row) {
  return message_from_row<causal_twin::Recommendation>(row);
}
std::optional<causal_twin::Prognosis> prognosis_from_row(const Row& row) {
  return message_from_row<causal_twin::Prognosis>(row);
}
std::optional<causal_twin::AssetStatus> status_from_row(const Row& row) {
  return message_from_row<causal_twin::AssetStatus>(row);
}

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
