// POST /api/approve: the page's approve button on a recommended lever (approval_request.hpp), handed to the DDS
// thread through ApprovalBridge, which writes it on twin-web's durable intervention writer. The pre-routing guard
// has already applied the what-if form's rules (Host, Origin, CSRF token, basic authentication) as to every
// state-changing request; the approver is the authenticated user.
#include "web_server.hpp"

#include "approval_request.hpp"
#include "json_reply.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <chrono>

namespace causal::web {

using nlohmann::json;

void WebServer::approve_route() {
  server_->Post("/api/approve", [this](const HttpRequest& req, HttpResponse& res) {
    if (approvals_ == nullptr || clock_ == nullptr) {
      send_unanswered(res, 503, "approvals are not available");
      return;
    }
    const std::optional<json> parsed = json_body(req, res);
    if (!parsed) return;
    const json& body = *parsed;
    ApprovalAsk ask;
    if (const std::string problem = parse_approval(body, guard_->user(), ask); !problem.empty()) {
      send_unanswered(res, 400, problem);
      return;
    }
    if (!ask.act.duration && options_.approval_duration > 0) ask.act.duration = options_.approval_duration;
    const PlannedApproval plan = plan_approval(ask, state_.group(ask.act.asset_group),
                                               clock_->latest(ask.act.asset_group), options_.approval_lead,
                                               io::utc_now_ns());
    if (plan.status != 200) {
      send_json(res, plan.status, {{"answered", false}, {"error", plan.why}, {"already", plan.already}});
      return;
    }
    const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.whatif_timeout_s * 1000.0));
    const ApprovalBridge::Outcome out = approvals_->ask(plan.intervention, timeout);
    if (out.status == ApprovalBridge::Status::Answered) {
      if (out.reply.published) {
        spdlog::info("approved from the page: {} by {} ({} readers matched)", plan.intervention.request_id(),
                     plan.intervention.approved_by(), out.reply.readers);
      }
      send_json(res, out.reply.published ? 200 : 409, approval_json(plan.intervention, out.reply));
      return;
    }
    send_json(res, 503, {{"answered", false},
                    {"error", out.status == ApprovalBridge::Status::Stopped ? "twin-web is stopping"
                                                                            : "the approval was not written in time"}});
  });
}

}  // namespace causal::web
