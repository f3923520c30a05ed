// causal-alarm-action's DDS node: one AlarmAction out on causal_twin/alarm_action, its AlarmActionResult in from
// causal_twin/alarm_action_result (applied or refused by alarm-recommender).
#pragma once

#include "causal/config/exit_codes.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <string>

namespace causal::alarm_action {

struct ActionOptions {
  dds::CommonOptions dds;
  std::string asset_group;
  std::string alarm_id;
  bool acknowledge = false;
  double shelve_minutes = 0.0;  // > 0: shelve for this long
  bool unshelve = false;
  std::string user;
  std::string reason;
  double timeout_s = 10.0;
};

// Exit codes of run() (2 is a usage error, before run()).
inline constexpr int kApplied = config::kExitOk;
inline constexpr int kNoResult = config::kExitNoPeer;  // no alarm-recommender on the domain, or no result in time
inline constexpr int kRefused = config::kExitLostOrRefused;   // the recommender refused the action (unknown alarm id, not applicable, ...)

class ActionNode {
 public:
  explicit ActionNode(ActionOptions options);  // throws std::invalid_argument for an invalid action
  int run();
  void stop() { loop_.stop(); }

 private:
  causal_twin::AlarmAction action() const;

  ActionOptions options_;
  dds::Participant participant_;
  dds::TypedWriter<causal_twin::AlarmActionPubSubType> actions_;
  dds::TypedReader<causal_twin::AlarmActionResultPubSubType> results_;
  dds::EventLoop loop_;
};

}  // namespace causal::alarm_action
