// What the AlarmManager tests share: their clocks and the alarm events and operator requests they feed it.
#pragma once

#include "causal/alarm_management/alarm_management.hpp"

#include <cstdint>
#include <string>

namespace causal::alarm_management::test {

inline constexpr std::int64_t kS = 1'000'000'000;
inline constexpr std::int64_t kT0 = 1'700'000'000 * kS;   // a data time
inline constexpr std::int64_t kNow = 1'800'000'000 * kS;  // a wall-clock time

// An alarm event of group g raised at `raised` (cleared a second later when state is Cleared).
inline AlarmEventView event(const std::string& id, EventState state, std::int64_t raised, const std::string& g = "g1") {
  return AlarmEventView{id, g, state, raised, state == EventState::Cleared ? raised + kS : 0};
}

// ann's request at kNow; a shelving gives its reason.
inline ActionRequest request(const std::string& rid, const std::string& alarm, ActionKind kind, std::int64_t until = 0,
                             const std::string& g = "g1") {
  ActionRequest r;
  r.request_id = rid;
  r.asset_group = g;
  r.alarm_id = alarm;
  r.action = kind;
  r.user = "ann";
  r.reason = kind == ActionKind::Shelve ? "sensor under repair" : "";
  r.time_ns = kNow;
  r.until_ns = until;
  return r;
}

}  // namespace causal::alarm_management::test
