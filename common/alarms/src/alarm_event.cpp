#include "causal/alarms/alarm_event.hpp"

#include <cstdio>
#include <utility>

#include "causal/estimation/state_archive.hpp"

namespace causal::alarms {

const char* to_string(Severity s) {
  switch (s) {
    case Severity::Advisory: return "advisory";
    case Severity::Warning: return "warning";
    case Severity::Critical: return "critical";
  }
  return "?";
}

const char* to_string(AlarmState s) {
  switch (s) {
    case AlarmState::Raised: return "raised";
    case AlarmState::Escalated: return "escalated";
    case AlarmState::Cleared: return "cleared";
  }
  return "?";
}

void save(causal::StateWriter& out, const AlarmEvent& e) {
  out.begin("alarm_event", 2);
  out.put(e.alarm_id);
  out.put(e.channel);
  out.put(static_cast<std::int32_t>(e.severity));
  out.put(static_cast<std::int32_t>(e.state));
  out.put(e.kind);
  out.put(e.raised_time_ns);
  out.put(e.cleared_time_ns);
  out.put(e.index);
  out.put(e.onset_index);
  out.put(e.onset_time_ns);
  out.put(e.root_cause_channel);
  out.put(e.factor_names);
  out.put(e.factor_baseline);
  out.put(e.factor_now);
  out.put(e.score);
  out.put(e.threshold);
  out.put(e.reason);
  out.put(e.category);
  out.put(e.root_cause_confidence);
}

void restore(causal::StateReader& in, AlarmEvent& event) {
  in.expect("alarm_event", 2);
  AlarmEvent e;
  in.read(e.alarm_id);
  in.read(e.channel);
  const auto severity = in.get<std::int32_t>();
  const auto state = in.get<std::int32_t>();
  if (severity < static_cast<int>(Severity::Advisory) || severity > static_cast<int>(Severity::Critical) ||
      state < static_cast<int>(AlarmState::Raised) || state > static_cast<int>(AlarmState::Cleared)) {
    throw causal::StateError("checkpoint: alarm_event '" + e.alarm_id + "' has an unknown severity or state");
  }
  e.severity = static_cast<Severity>(severity);
  e.state = static_cast<AlarmState>(state);
  in.read(e.kind);
  in.read(e.raised_time_ns);
  in.read(e.cleared_time_ns);
  in.read(e.index);
  in.read(e.onset_index);
  in.read(e.onset_time_ns);
  in.read(e.root_cause_channel);
  in.read(e.factor_names);
  in.read(e.factor_baseline);
  in.read(e.factor_now);
  in.read(e.score);
  in.read(e.threshold);
  in.read(e.reason);
  in.read(e.category);
  in.read(e.root_cause_confidence);
  event = std::move(e);
}

std::string format_utc_seconds(std::int64_t time_ns) {
  // Floor division so times before 1970 still land on the right second.
  std::int64_t secs = time_ns / 1000000000LL;
  if (time_ns % 1000000000LL < 0) --secs;
  std::int64_t days = secs / 86400;
  std::int64_t sod = secs % 86400;
  if (sod < 0) {
    sod += 86400;
    --days;
  }
  // Howard Hinnant's civil_from_days: proleptic Gregorian date from days since 1970-01-01.
  const std::int64_t z = days + 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const std::int64_t doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const std::int64_t mp = (5 * doy + 2) / 153;
  const std::int64_t d = doy - (153 * mp + 2) / 5 + 1;
  const std::int64_t m = mp < 10 ? mp + 3 : mp - 9;
  const std::int64_t y = yoe + era * 400 + (m <= 2 ? 1 : 0);
  char buf[48];
  std::snprintf(buf, sizeof buf, "%04lld-%02lld-%02lld %02lld:%02lld:%02lld UTC", static_cast<long long>(y),
                static_cast<long long>(m), static_cast<long long>(d), static_cast<long long>(sod / 3600),
                static_cast<long long>((sod / 60) % 60), static_cast<long long>(sod % 60));
  return buf;
}

}  // namespace causal::alarms
