// The closed loop in /api/state and the page's group JSON: a group's approved interventions, each with the twin's
// check of it once published (twin_state_interventions.cpp).
#pragma once

#include "twin_state.hpp"

#include <nlohmann/json.hpp>

namespace causal::web {

// Oldest first (by arrival). Per entry: request_id, channel (1-based) and channel_name, change_percent,
// start_index, end_index (last snapshot of the window), duration, start_time_ms, recommendation_id,
// target_channel and target_name, approved_by, approved_time_ms; null fields for an outcome whose approval was
// not seen; outcome: null until checked, else status, predicted_percent(_low/_high), confidence,
// observed_percent, inside, improved, lever_trust, lever_claimed, text. Non-finite numbers are null.
nlohmann::json interventions_json(const GroupState& g);

}  // namespace causal::web
