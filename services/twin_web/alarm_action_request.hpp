// The page's alarm action (POST /api/alarm_action) checked and turned into the DDS message, and the result as JSON.
// HTTP-free, so it is unit-tested on its own (tests/browser).
//   body: {"asset_group", "alarm_id", "action": "acknowledge" | "shelve" | "unshelve", "minutes" (shelve, > 0,
//          <= 10080), "reason" (required to shelve), "user" (when twin-web does not authenticate)}
// With basic authentication the user is the authenticated one (a body cannot act in another's name).
#pragma once

#include "causal_twin.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace causal::web {

// Fills `out` (all but request_id); returns the first problem, or "".
std::string parse_alarm_action(const nlohmann::json& body, const std::string& authenticated_user, std::int64_t now_ns,
                               causal_twin::AlarmAction& out);
nlohmann::json alarm_action_result_json(const causal_twin::AlarmActionResult& result);

}  // namespace causal::web
