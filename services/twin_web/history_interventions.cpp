#include "history_interventions.hpp"

#include "history_cells.hpp"

#include <string>

namespace causal::web {

// Both tables' integer cells are always written (required): an empty one makes the row unreadable.
std::optional<causal_twin::Intervention> intervention_from_row(const history::Row& row) {
  return message_from_row<causal_twin::Intervention>(row, RowFields::Integers::Required);
}

std::optional<causal_twin::InterventionOutcome> intervention_outcome_from_row(const history::Row& row) {
  return message_from_row<causal_twin::InterventionOutcome>(row, RowFields::Integers::Required);
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
