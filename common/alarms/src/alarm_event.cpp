#include "causal/alarms/alarm_event.hpp"

#include <utility>

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

namespace causal::alarms {

const char* to_string(Severity s) {
  switch (s) {
    case Severity::Advisory: return "advisory";
    case Severity::Warning: return "warning";
    case Severity::Critical: return "critical";
  }
  return "?";
}

std::optional<Severity> parse_severity(std::string_view text) {
  for (const Severity s : {Severity::Advisory, Severity::Warning, Severity::Critical}) {
    if (text == to_string(s)) return s;
  }
  return std::nullopt;
}

const char* to_string(AlarmState s) {
  switch (s) {
    case AlarmState::Raised: return "raised";
    case AlarmState::Escalated: return "escalated";
    case AlarmState::Cleared: return "cleared";
  }
  return "?";
}

namespace {

// The event's fields after its severity and state (both written as int32 and checked on restore); one list
// for save and restore (SaveFields / RestoreFields, state_fields.hpp).
template <class Io, class E>
void fields_after_state(Io io, E& e) {
  io(e.kind, e.raised_time_ns, e.cleared_time_ns, e.index, e.onset_index, e.onset_time_ns, e.root_cause_channel,
     e.factor_names, e.factor_baseline, e.factor_now, e.score, e.threshold, e.reason, e.category,
     e.root_cause_confidence);
}

}  // namespace

void save(estimation::StateWriter& out, const AlarmEvent& e) {
  out.begin("alarm_event", 2);
  out.put(e.alarm_id);
  out.put(e.channel);
  out.put(static_cast<std::int32_t>(e.severity));
  out.put(static_cast<std::int32_t>(e.state));
  fields_after_state(estimation::SaveFields{out}, e);
}

void restore(estimation::StateReader& in, AlarmEvent& event) {
  in.expect("alarm_event", 2);
  AlarmEvent e;
  in.read(e.alarm_id);
  in.read(e.channel);
  const auto severity = in.get<std::int32_t>();
  const auto state = in.get<std::int32_t>();
  if (severity < static_cast<int>(Severity::Advisory) || severity > static_cast<int>(Severity::Critical) ||
      state < static_cast<int>(AlarmState::Raised) || state > static_cast<int>(AlarmState::Cleared)) {
    throw estimation::StateError("checkpoint: alarm_event '" + e.alarm_id + "' has an unknown severity or state");
  }
  e.severity = static_cast<Severity>(severity);
  e.state = static_cast<AlarmState>(state);
  fields_after_state(estimation::RestoreFields{in}, e);
  event = std::move(e);
}

}  // namespace causal::alarms
