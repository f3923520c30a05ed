// The page's approve button (POST /api/approve) checked and turned into the intervention causal-approve would
// publish for the same act (common/dds/include/causal/dds/approval.hpp: same fields, same request id), and the answer as
// JSON. HTTP-free and DDS-free, so it is unit-tested on its own (tests/browser).
//   body: {"asset_group", "recommendation_id", "duration_snapshots" (optional, 1..1000000: the change is held so
//          long; default the recommendation's horizon, at least 12), "user" (when twin-web does not authenticate)}
// With basic authentication the approver is the authenticated user (a body cannot approve in another's name).
#pragma once

#include "request_bridge.hpp"
#include "twin_state.hpp"

#include "causal/dds/approval.hpp"
#include "causal_twin.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

namespace causal::web {

struct ApprovalAsk {
  dds::ApprovalAct act;
  std::string recommendation_id;
};

// Fills `out`; returns the first problem, or "".
std::string parse_approval(const nlohmann::json& body, const std::string& authenticated_user, ApprovalAsk& out);

// The plant's own clock per asset group, from the source's condition inputs (causal_twin/condition_input): its
// latest snapshot index, that snapshot's time and the cadence between two consecutive ones. An approval starts
// from here, not from the estimator's output, which lags the plant. DDS thread writes, web threads read.
class SourceClock {
 public:
  struct Reading {
    std::uint64_t index = 0;
    std::int64_t time_ns = 0, cadence_ns = 0;
  };
  void on_input(const std::string& asset_group, std::uint64_t index, std::int64_t time_ns);
  std::optional<Reading> latest(const std::string& asset_group) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, Reading> groups_;
};

// The intervention for approving `ask` in `group` (the state twin-web holds of it): found among the group's
// recommendations, not yet approved, and starting `lead` snapshots after the plant's latest snapshot (the source's
// clock, else the estimator's latest condition vector, else the recommendation's own index). `status` is the
// HTTP answer when it is not approvable (404 unknown, 409 not a lever, already approved or overlapping an approved
// change of the same channel), with `why`.
struct PlannedApproval {
  int status = 200;
  std::string why;
  std::string already;  // the request id of the earlier approval of the same recommendation
  causal_twin::Intervention intervention;
};
PlannedApproval plan_approval(const ApprovalAsk& ask, const std::optional<GroupState>& group,
                              const std::optional<SourceClock::Reading>& clock, std::uint64_t lead,
                              std::int64_t now_ns);

// The DDS thread's answer for one approval handed to it: written on twin-web's durable intervention writer (kept
// there for readers that join later), or refused (an approval of the same recommendation already written, the
// writer's own grant does not name the group, the write failed).
struct ApprovalResult {
  std::string id;
  bool published = false;
  std::string error;
  std::string already;   // with a refusal for an earlier approval: its request id
  std::size_t readers = 0;  // intervention readers matched when it was written
  const std::string& request_id() const { return id; }
};
using ApprovalBridge = RequestBridge<causal_twin::Intervention, ApprovalResult>;

nlohmann::json approval_json(const causal_twin::Intervention& iv, const ApprovalResult& result);

}  // namespace causal::web
