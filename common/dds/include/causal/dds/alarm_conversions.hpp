// IDL <-> core conversions for alarms.
#pragma once

#include "causal/alarms/alarm_event.hpp"
#include "causal_twin.h"

#include <optional>
#include <string>
#include <vector>

namespace causal::dds {

// The core enums <-> the IDL enums. from_idl is nullopt for a value outside the IDL enum (a foreign writer).
causal_twin::Severity to_idl(alarms::Severity s);
causal_twin::AlarmState to_idl(alarms::AlarmState s);
std::optional<alarms::Severity> from_idl(causal_twin::Severity s);
std::optional<alarms::AlarmState> from_idl(causal_twin::AlarmState s);
// An IDL value spelt as the core spells it (alarms::to_string); `unknown` for a value outside the enum.
const char* to_string(causal_twin::Severity s, const char* unknown);
const char* to_string(causal_twin::AlarmState s, const char* unknown);
// An alarm action as alarm_management::to_string spells its ActionKind: "acknowledge" | "shelve" | "unshelve".
const char* to_string(causal_twin::AlarmActionKind k, const char* unknown);

// channel_names: the asset group's G names (0-based channels in the event become 1-based in the message).
void to_alarm(const std::string& asset_group, const std::vector<std::string>& channel_names,
              const alarms::AlarmEvent& event, causal_twin::Alarm& out);

}  // namespace causal::dds
