#include "action_node.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

namespace causal::alarm_action {

namespace {

using Clock = std::chrono::steady_clock;

std::string request_id() {
  char host[128] = "host";
  gethostname(host, sizeof host - 1);
  return std::string("causal-alarm-action/") + host + "/" + std::to_string(getpid()) + "/" +
         std::to_string(io::utc_now_ns());
}

void check(const ActionOptions& o) {
  if ((o.acknowledge ? 1 : 0) + (o.shelve_minutes > 0.0 ? 1 : 0) + (o.unshelve ? 1 : 0) != 1) {
    throw std::invalid_argument("give exactly one of --ack, --shelve MINUTES and --unshelve");
  }
  if (o.asset_group.empty()) throw std::invalid_argument("--group must not be empty");
  if (o.alarm_id.empty()) throw std::invalid_argument("--alarm must not be empty");
  if (o.user.empty()) throw std::invalid_argument("--user must not be empty");
  if (o.shelve_minutes > 0.0 && o.reason.empty()) throw std::invalid_argument("--shelve needs --reason TEXT");
}

}  // namespace

ActionNode::ActionNode(ActionOptions options)
    : options_((check(options), std::move(options))),
      participant_(dds::to_dds_settings(options_.dds, "causal-alarm-action")),
      actions_(participant_, dds::topics::kAlarmAction, dds::profiles::kAlarmActionWriter),
      results_(participant_, dds::topics::kAlarmActionResult, dds::profiles::kAlarmActionResultReader) {
  loop_.attach(results_.get());
}

causal_twin::AlarmAction ActionNode::action() const {
  causal_twin::AlarmAction a;
  a.request_id(request_id());
  a.asset_group(options_.asset_group);
  a.alarm_id(options_.alarm_id);
  a.user_name(options_.user);
  a.reason(options_.reason);
  a.time_ns(io::utc_now_ns());
  if (options_.shelve_minutes > 0.0) {
    a.action(causal_twin::SHELVE);
    a.until_ns(a.time_ns() + static_cast<std::int64_t>(std::llround(options_.shelve_minutes * 60e9)));
  } else {
    a.action(options_.unshelve ? causal_twin::UNSHELVE : causal_twin::ACKNOWLEDGE);
  }
  return a;
}

int ActionNode::run() {
  const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.timeout_s * 1000.0));
  const auto deadline = Clock::now() + timeout;
  if (!actions_.wait_for_readers(1, timeout, loop_.stop_flag())) {
    if (!loop_.stopped()) {
      spdlog::error("no alarm-recommender reads alarm actions on domain {} (waited {:.0f} s)", participant_.domain_id(),
                    options_.timeout_s);
    }
    return kNoResult;
  }
  // Sent once: the recommender answers a re-delivered request id with its first result, and results are
  // transient-local (kept per request id), so a result written before this reader matched still arrives.
  causal_twin::AlarmAction a = action();
  if (actions_.write(a, loop_.stop_flag(), timeout) != dds::WriteResult::Ok) {
    spdlog::error("alarm action not sent (DDS return code {})", actions_.last_error());
    return kNoResult;
  }
  while (!loop_.stopped() && Clock::now() < deadline) {
    std::optional<causal_twin::AlarmActionResult> result;
    loop_.wait(std::chrono::milliseconds(100));
    results_.take_all([&](const causal_twin::AlarmActionResult& r, const auto&) {
      if (r.request_id() == a.request_id()) result = r;
    });
    if (!result) continue;
    const char* verb = dds::to_string(a.action(), "unknown");
    if (!result->applied()) {
      std::printf("refused: %s %s: %s\n", verb, a.alarm_id().c_str(), result->error().c_str());
      return kRefused;
    }
    std::printf("applied: %s %s by %s (acknowledged %s, shelved %s)\n", verb, a.alarm_id().c_str(),
                a.user_name().c_str(), result->acknowledged() ? "yes" : "no", result->shelved() ? "yes" : "no");
    return kApplied;
  }
  if (!loop_.stopped()) spdlog::error("no result for alarm action {} within {:.0f} s", a.request_id(), options_.timeout_s);
  return kNoResult;
}

}  // namespace causal::alarm_action
