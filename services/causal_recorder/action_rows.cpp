#include "action_rows.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/time_format.hpp"

namespace causal::recorder {

const std::vector<std::string>& alarm_action_header() {
  static const std::vector<std::string> h{"action_id", "asset_group", "alarm_id", "action",  "user_name",
                                          "reason",    "time_utc",    "until_utc", "time_ns", "until_ns"};
  return h;
}

const char* action_name(causal_twin::AlarmActionKind kind) {
  switch (kind) {
    case causal_twin::ACKNOWLEDGE: return "acknowledge";
    case causal_twin::SHELVE: return "shelve";
    case causal_twin::UNSHELVE: return "unshelve";
  }
  return "unknown";
}

std::vector<std::string> alarm_action_row(const causal_twin::AlarmActionResult& r) {
  return {r.request_id(),
          r.asset_group(),
          r.alarm_id(),
          action_name(r.action()),
          r.user_name(),
          r.reason(),
          r.time_ns() == 0 ? std::string() : io::format_utc(r.time_ns()),
          r.until_ns() == 0 ? std::string() : io::format_utc(r.until_ns()),
          io::format_integer(static_cast<std::int64_t>(r.time_ns())),
          io::format_integer(static_cast<std::int64_t>(r.until_ns()))};
}

}  // namespace causal::recorder
