#include "alarm_action_request.hpp"

#include "request_fields.hpp"

#include "causal/dds/alarm_conversions.hpp"

#include <cmath>

namespace causal::web {

using nlohmann::json;

namespace {

constexpr double kMaxShelveMinutes = 10080.0;  // a week: alarm-recommender refuses longer shelvings

}  // namespace

std::string parse_alarm_action(const json& body, const std::string& authenticated_user, std::int64_t now_ns,
                               causal_twin::AlarmAction& out) {
  if (!body.is_object()) return "the body must be a JSON object";
  std::string group, alarm, action, reason, user;
  if (auto why = required_id(body, "asset_group", group); !why.empty()) return why;
  if (auto why = required_id(body, "alarm_id", alarm); !why.empty()) return why;
  if (!text_field(body, "action", 16, action)) return "action must be acknowledge, shelve or unshelve";
  if (!text_field(body, "reason", 255, reason)) return "reason must be a string of at most 255 bytes";
  if (auto why = acting_user(body, authenticated_user, user); !why.empty()) return why;
  out.asset_group(group);
  out.alarm_id(alarm);
  out.user_name(user);
  out.reason(reason);
  out.time_ns(now_ns);
  out.until_ns(0);
  if (action == "acknowledge") {
    out.action(causal_twin::ACKNOWLEDGE);
  } else if (action == "unshelve") {
    out.action(causal_twin::UNSHELVE);
  } else if (action == "shelve") {
    if (!body.contains("minutes") || !body["minutes"].is_number()) return "minutes (number) is required to shelve";
    const double minutes = body["minutes"].get<double>();
    if (!std::isfinite(minutes) || minutes <= 0.0 || minutes > kMaxShelveMinutes) {
      return "minutes must be > 0 and at most 10080 (a week)";
    }
    if (reason.empty()) return "a reason is required to shelve";
    out.action(causal_twin::SHELVE);
    out.until_ns(now_ns + static_cast<std::int64_t>(std::llround(minutes * 60e9)));
  } else {
    return "action must be acknowledge, shelve or unshelve";
  }
  return {};
}

json alarm_action_result_json(const causal_twin::AlarmActionResult& r) {
  return {{"answered", true},
          {"applied", r.applied()},
          {"error", r.error()},
          {"request_id", r.request_id()},
          {"asset_group", r.asset_group()},
          {"alarm_id", r.alarm_id()},
          {"action", dds::to_string(r.action(), "unknown")},
          {"user", r.user_name()},
          {"acknowledged", r.acknowledged()},
          {"shelved", r.shelved()},
          {"until_ms", r.until_ns() / 1'000'000}};
}

}  // namespace causal::web
