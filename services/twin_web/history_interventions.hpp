// twin-web's history (--db) for the closed loop: the historian's interventions and intervention_outcomes rows
// turned back into the messages, so a restarted twin-web shows the approvals whose writer (causal-approve) is long
// gone, with their outcomes. Rows that do not convert are counted, never shown half.
#pragma once

#include "twin_state.hpp"

#include "causal/history/history_store.hpp"

#include <cstdint>
#include <optional>

namespace causal::web {

struct InterventionLoad {
  std::uint64_t approvals = 0, outcomes = 0;
  std::uint64_t unreadable = 0;
};

// Every approval, then every outcome (each in start-snapshot order), into state.
InterventionLoad load_interventions(history::HistoryStore& store, TwinState& state);

std::optional<causal_twin::Intervention> intervention_from_row(const history::Row& row);
std::optional<causal_twin::InterventionOutcome> intervention_outcome_from_row(const history::Row& row);

}  // namespace causal::web
