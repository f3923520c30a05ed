#include "causal/alarms/alarm_event.hpp"

#include <utility>

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"
#include "causal/io/enum_names.hpp"

namespace causal::alarms {

namespace {

constexpr auto kSeverityNames = io::enum_names<Severity>(
    {{Severity::Advisory, "advisory"}, {Severity::Warning, "warning"}, {Severity::Critical, "critical"}});

constexpr auto kStateNames = io::enum_names<AlarmState>(
    {{AlarmState::Raised, "raised"}, {AlarmState::Escalated, "escalated"}, {AlarmState::Cleared, "cleared"}});

}  // namespace

const char* to_string(Severity s) { return kSeverityNames.name(s, "?"); }

std::optional<Severity> parse_severity(std::string_view text) { return kSeverityNames.parse(text); }

const char* to_string(AlarmState s) { return kStateNames.name(s, "?"); }

namespace {

// The event's field list (SaveFields / RestoreFields, state_fields.hpp); severity and state are written as int32
// and checked on restore.
template <class Io, class E>
void event_fields(Io io, E& e) {
  io.tag("alarm_event", 2);
  io(e.alarm_id, e.channel);
  io.template as<std::int32_t>(e.severity);
  io.template as<std::int32_t>(e.state);
  if constexpr (Io::restoring) {
    const auto severity = static_cast<int>(e.severity);
    const auto state = static_cast<int>(e.state);
    if (severity < static_cast<int>(Severity::Advisory) || severity > static_cast<int>(Severity::Critical) ||
        state < static_cast<int>(AlarmState::Raised) || state > static_cast<int>(AlarmState::Cleared)) {
      throw estimation::StateError("checkpoint: alarm_event '" + e.alarm_id + "' has an unknown severity or state");
    }
  }
  io(e.kind, e.raised_time_ns, e.cleared_time_ns, e.index, e.onset_index, e.onset_time_ns, e.root_cause_channel,
     e.factor_names, e.factor_baseline, e.factor_now, e.score, e.threshold, e.reason, e.category,
     e.root_cause_confidence);
}

}  // namespace

void save(estimation::StateWriter& out, const AlarmEvent& e) { event_fields(estimation::SaveFields{out}, e); }

void restore(estimation::StateReader& in, AlarmEvent& event) {
  AlarmEvent e;  // restored aside: a damaged checkpoint leaves `event` as it was
  event_fields(estimation::RestoreFields{in}, e);
  event = std::move(e);
}

}  // namespace causal::alarms
