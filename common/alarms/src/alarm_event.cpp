#include "causal/alarms/alarm_event.hpp"

#include <cstdio>

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
