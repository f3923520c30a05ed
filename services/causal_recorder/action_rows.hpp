// causal-recorder: rows of alarm_actions.csv and the historian's alarm_actions table, one per alarm action that
// alarm-recommender applied (causal_twin/alarm_action_result: acknowledge, shelve, unshelve, and shelvings that
// expired by themselves). Refused actions changed nothing: they are counted, not stored.
#pragma once

#include "causal_twin.h"

#include <string>
#include <vector>

namespace causal::recorder {

inline constexpr const char* kAlarmActionsFile = "alarm_actions.csv";
// action_id,asset_group,alarm_id,action,user_name,reason,time_utc,until_utc,time_ns,until_ns (the table's columns;
// until is empty / 0 but for a shelving).
const std::vector<std::string>& alarm_action_header();
std::vector<std::string> alarm_action_row(const causal_twin::AlarmActionResult& r);
// "acknowledge" | "shelve" | "unshelve".
const char* action_name(causal_twin::AlarmActionKind kind);

}  // namespace causal::recorder
