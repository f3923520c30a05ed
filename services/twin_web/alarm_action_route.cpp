// POST /api/alarm_action: the page's acknowledge / shelve / unshelve (alarm_action_request.hpp), sent to
// alarm-recommender through AlarmActionBridge. The pre-routing guard has already applied the what-if form's rules
// (Host, Origin, CSRF token, basic authentication) as to every state-changing request.
#include "web_server.hpp"

#include "alarm_action_request.hpp"
#include "json_reply.hpp"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace causal::web {

using nlohmann::json;

void WebServer::alarm_action_route() {
  server_->Post("/api/alarm_action", [this](const HttpRequest& req, HttpResponse& res) {
    if (actions_ == nullptr) {
      send_unanswered(res, 503, "alarm actions are not available");
      return;
    }
    const std::optional<json> parsed = json_body(req, res);
    if (!parsed) return;
    const json& body = *parsed;
    causal_twin::AlarmAction action;
    if (const std::string problem = parse_alarm_action(body, guard_->user(), io::utc_now_ns(), action);
        !problem.empty()) {
      send_unanswered(res, 400, problem);
      return;
    }
    char host[128] = "host";
    gethostname(host, sizeof host - 1);
    action.request_id("twin-web/" + std::string(host) + "/" + std::to_string(getpid()) + "/action/" +
                      std::to_string(++next_request_));
    const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.whatif_timeout_s * 1000.0));
    const AlarmActionBridge::Outcome out = actions_->ask(action, timeout);
    if (out.status == AlarmActionBridge::Status::Answered) {
      // Refused: 409 (the request was well formed; the alarm's state does not allow it, or the id is unknown).
      send_json(res, out.reply.applied() ? 200 : 409, alarm_action_result_json(out.reply));
      return;
    }
    if (out.status == AlarmActionBridge::Status::Stopped) {
      send_unanswered(res, 503, "twin-web is stopping");
      return;
    }
    char msg[160];
    std::snprintf(msg, sizeof msg, "no result within %.0f s: is alarm-recommender running?", options_.whatif_timeout_s);
    send_unanswered(res, 504, msg);
  });
}

}  // namespace causal::web
