#include "status_rows.hpp"

#include "causal/io/csv_format.hpp"
#include "record_rows.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/io/time_format.hpp"

namespace causal::recorder {

using io::format_integer;

const std::vector<std::string>& asset_status_header() {
  static const std::vector<std::string> h{"asset_group",     "state",           "learning_seen",  "learning_needed",
                                          "sample_index",    "time_utc",        "has_alarm",      "worst_severity",
                                          "open_alarms",     "root_cause_channel", "root_cause_name", "action",
                                          "prognosis_text",  "text",
                                          "unacknowledged_alarms", "shelved_alarms", "alarms_per_10_min", "alarm_flood",
                                          "standing_alarms", "chattering_alarms"};
  return h;
}

std::vector<std::string> asset_status_row(const causal_twin::AssetStatus& s) {
  return {s.asset_group(),
          s.state(),
          format_integer(static_cast<std::uint64_t>(s.learning_seen())),
          format_integer(static_cast<std::uint64_t>(s.learning_needed())),
          format_integer(static_cast<std::uint64_t>(s.sample_index())),
          s.time_ns() == 0 ? std::string() : io::format_utc(s.time_ns()),
          s.has_alarm() ? "true" : "false",
          s.has_alarm() ? dds::to_string(s.worst_severity(), "?") : "",
          format_integer(static_cast<std::uint64_t>(s.open_alarms())),
          format_integer(static_cast<std::uint64_t>(s.root_cause_channel())),
          s.root_cause_name(),
          s.action(),
          s.prognosis_text(),
          s.text(),
          format_integer(static_cast<std::uint64_t>(s.unacknowledged_alarms())),
          format_integer(static_cast<std::uint64_t>(s.shelved_alarms())),
          format_integer(static_cast<std::uint64_t>(s.alarms_per_10_min())),
          s.alarm_flood() ? "true" : "false",
          format_integer(static_cast<std::uint64_t>(s.standing_alarms())),
          format_integer(static_cast<std::uint64_t>(s.chattering_alarms()))};
}

std::string asset_status_signature(const causal_twin::AssetStatus& s) {
  std::string out;
  for (const auto& cell : asset_status_row(s)) out += cell + '\x1f';
  return out;
}

}  // namespace causal::recorder
