#include "causal/dds/alarm_conversions.hpp"

#include <limits>

#include "causal/io/enum_names.hpp"

namespace causal::dds {

namespace {

// The core enums and their IDL twins, each pair once: to_idl reads them one way, from_idl the other.
constexpr auto kSeverityIdl = io::enum_map<alarms::Severity, causal_twin::Severity>(
    {{alarms::Severity::Advisory, causal_twin::ADVISORY},
     {alarms::Severity::Warning, causal_twin::WARNING},
     {alarms::Severity::Critical, causal_twin::CRITICAL}});

constexpr auto kStateIdl = io::enum_map<alarms::AlarmState, causal_twin::AlarmState>(
    {{alarms::AlarmState::Raised, causal_twin::RAISED},
     {alarms::AlarmState::Escalated, causal_twin::ESCALATED},
     {alarms::AlarmState::Cleared, causal_twin::CLEARED}});

}  // namespace

causal_twin::Severity to_idl(alarms::Severity s) { return kSeverityIdl.at(s, causal_twin::ADVISORY); }

causal_twin::AlarmState to_idl(alarms::AlarmState s) { return kStateIdl.at(s, causal_twin::RAISED); }

std::optional<alarms::Severity> from_idl(causal_twin::Severity s) { return kSeverityIdl.find(s); }

std::optional<alarms::AlarmState> from_idl(causal_twin::AlarmState s) { return kStateIdl.find(s); }

const char* to_string(causal_twin::Severity s, const char* unknown) {
  const auto core = from_idl(s);
  return core ? alarms::to_string(*core) : unknown;
}

const char* to_string(causal_twin::AlarmState s, const char* unknown) {
  const auto core = from_idl(s);
  return core ? alarms::to_string(*core) : unknown;
}

const char* to_string(causal_twin::AlarmActionKind k, const char* unknown) {
  switch (k) {
    case causal_twin::ACKNOWLEDGE: return "acknowledge";
    case causal_twin::SHELVE: return "shelve";
    case causal_twin::UNSHELVE: return "unshelve";
  }
  return unknown;
}

namespace {
std::string name_of(const std::vector<std::string>& names, int channel) {
  return channel >= 0 && static_cast<std::size_t>(channel) < names.size() ? names[static_cast<std::size_t>(channel)]
                                                                          : std::string();
}
}  // namespace

void to_alarm(const std::string& asset_group, const std::vector<std::string>& channel_names,
              const alarms::AlarmEvent& e, causal_twin::Alarm& out) {
  out.alarm_id(e.alarm_id);
  out.asset_group(asset_group);
  out.channel(static_cast<uint16_t>(e.channel + 1));
  out.channel_name(name_of(channel_names, e.channel));
  out.severity(to_idl(e.severity));
  out.state(to_idl(e.state));
  out.kind(e.kind);
  out.category(e.category);  // degradation or operating_change; data-quality/health alarms set their own
  out.raised_time_ns(e.raised_time_ns);
  out.cleared_time_ns(e.cleared_time_ns);
  out.sample_index(e.index);
  out.root_cause_channel(static_cast<uint16_t>(e.root_cause_channel >= 0 ? e.root_cause_channel + 1 : 0));
  out.root_cause_name(name_of(channel_names, e.root_cause_channel));
  out.factor_names(e.factor_names);
  out.factor_baseline(e.factor_baseline);
  out.factor_now(e.factor_now);
  out.score(e.score);
  out.threshold(e.threshold);
  out.reason(e.reason);
  out.root_cause_confidence(e.root_cause_confidence);
  // The decision fields are filled by the advice (alarm-recommender) when it has one; until then: none, unknown.
  out.action(std::string());
  out.next_level(std::string());
  out.hours_to_next_level(std::numeric_limits<double>::quiet_NaN());
  out.hours_to_next_level_low(std::numeric_limits<double>::quiet_NaN());
  out.hours_to_next_level_high(std::numeric_limits<double>::quiet_NaN());
}

}  // namespace causal::dds
