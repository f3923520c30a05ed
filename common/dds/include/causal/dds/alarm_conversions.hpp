// IDL <-> core conversions for alarms.
#pragma once

#include "causal/alarms/alarm_event.hpp"
#include "causal_twin.h"

#include <string>
#include <vector>

namespace causal::dds {

// channel_names: the asset group's G names (0-based channels in the event become 1-based in the message).
void to_alarm(const std::string& asset_group, const std::vector<std::string>& channel_names,
              const alarms::AlarmEvent& event, causal_twin::Alarm& out);

}  // namespace causal::dds
