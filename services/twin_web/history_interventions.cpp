#include "history_interventions.hpp"

#include "history_cells.hpp"

#include <string>

namespace causal::web {

namespace {

using history::Row;

causal_twin::Intervention make_intervention(const Row& row) {
  const HistoryCells c("interventions", row);
  causal_twin::Intervention i;
  i.request_id(c.text("request_id"));
  i.asset_group(c.text("asset_group"));
  i.channel(static_cast<std::uint16_t>(c.required_integer("channel")));
  i.change_percent(c.real("change_percent"));
  i.start_snapshot_index(static_cast<std::uint64_t>(c.required_integer("start_snapshot_index")));
  i.start_time_ns(c.required_integer("start_time_ns"));
  i.duration_snapshots(static_cast<std::uint32_t>(c.required_integer("duration_snapshots")));
  i.recommendation_id(c.text("recommendation_id"));
  i.target_channel(static_cast<std::uint16_t>(c.required_integer("target_channel")));
  i.approved_by(c.text("approved_by"));
  i.approved_time_ns(c.required_integer("approved_time_ns"));
  return i;
}

causal_twin::InterventionOutcome make_outcome(const Row& row) {
  const HistoryCells c("intervention_outcomes", row);
  causal_twin::InterventionOutcome o;
  o.request_id(c.text("request_id"));
  o.asset_group(c.text("asset_group"));
  o.recommendation_id(c.text("recommendation_id"));
  o.channel(static_cast<std::uint16_t>(c.required_integer("channel")));
  o.target_channel(static_cast<std::uint16_t>(c.required_integer("target_channel")));
  o.start_snapshot_index(static_cast<std::uint64_t>(c.required_integer("start_snapshot_index")));
  o.end_snapshot_index(static_cast<std::uint64_t>(c.required_integer("end_snapshot_index")));
  o.status(c.text("status"));
  o.predicted_percent(c.real("predicted_percent"));
  o.predicted_percent_low(c.real("predicted_percent_low"));
  o.predicted_percent_high(c.real("predicted_percent_high"));
  o.confidence(c.real("confidence"));
  o.observed_percent(c.real("observed_percent"));
  o.inside(c.boolean("inside"));
  o.improved(c.boolean("improved"));
  o.lever_trust(c.real("lever_trust"));
  o.lever_claimed(c.boolean("lever_claimed"));
  o.text(c.text("text"));
  return o;
}

}  // namespace

std::optional<causal_twin::Intervention> intervention_from_row(const Row& row) {
  return guarded(make_intervention, row);
}

std::optional<causal_twin::InterventionOutcome> intervention_outcome_from_row(const Row& row) {
  return guarded(make_outcome, row);
}

InterventionLoad load_interventions(history::HistoryStore& store, TwinState& state) {
  InterventionLoad out;
  const auto approvals = store.select(history::table("interventions"), {});
  for (const auto& x : readable(approvals, intervention_from_row, out.unreadable)) {
    state.on_intervention(x);
    ++out.approvals;
  }
  const auto outcomes = store.select(history::table("intervention_outcomes"), {});
  for (const auto& x : readable(outcomes, intervention_outcome_from_row, out.unreadable)) {
    state.on_intervention_outcome(x);
    ++out.outcomes;
  }
  return out;
}

}  // namespace causal::web
