// TwinState: operators' alarm actions as alarm-recommender applied them (causal_twin/alarm_action_result). An
// acknowledgement marks its alarm id; a shelving (and its end, by an operator or by expiry) marks every alarm of the
// same source (the id without its counter), as the recommender shelves the source.
#include "twin_state.hpp"

namespace causal::web {

namespace {

std::string source_of(const std::string& alarm_id) {
  const auto slash = alarm_id.rfind('/');
  return slash == std::string::npos ? alarm_id : alarm_id.substr(0, slash);
}

}  // namespace

void TwinState::on_action_result(const causal_twin::AlarmActionResult& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!in.applied()) {
    ++counters_.alarm_actions_refused;
    return;
  }
  ++counters_.alarm_actions;
  GroupState& g = group_locked(in.asset_group());
  if (in.action() == causal_twin::ACKNOWLEDGE) {
    const auto it = g.alarms.find(in.alarm_id());
    if (it != g.alarms.end()) {
      it->second.acknowledged = true;
      it->second.acknowledged_by = in.user_name();
    }
  } else {
    const std::string source = source_of(in.alarm_id());
    const bool shelve = in.action() == causal_twin::SHELVE;
    for (auto& [id, a] : g.alarms) {
      if (source_of(id) != source) continue;
      a.shelved = shelve;
      a.shelved_until_ns = shelve ? in.until_ns() : 0;
      a.shelved_by = shelve ? in.user_name() : "";
      a.shelve_reason = shelve ? in.reason() : "";
    }
  }
  changed_locked(&g, true);
}

}  // namespace causal::web
