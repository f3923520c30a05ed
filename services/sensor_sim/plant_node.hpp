// sensor-sim's condition-level plant mode (--plant): simulated plants (level_plant.hpp) publish one condition
// vector per group and snapshot on causal_twin/condition_input, and obey approved interventions read from
// causal_twin/intervention: each is applied to its group's true structural model as the do-operation (P2) from
// its start snapshot index, so the data depend on the approvals and their indices only (same input, same output).
// An intervention for another group is not ours (counted, ignored); one that cannot be applied as approved
// (its start already published, a bad channel or size, an overlap) is refused, logged and counted (exit 4), and
// so is one whose writer may not approve for its group (intervention_inbox.hpp: not_entitled).
#pragma once

#include "intervention_inbox.hpp"
#include "level_plant.hpp"
#include "sim_options.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace causal::sim {

class PlantNode {
 public:
  explicit PlantNode(SimOptions options);
  int run();
  void stop();

 private:
  struct Group {
    std::string id;
    LevelPlant plant;
  };
  using Clock = std::chrono::steady_clock;

  bool sleep_until(Clock::time_point due);
  void take_interventions();  // before every snapshot: applies what arrived
  void apply(const causal_twin::Intervention& in);
  bool publish_snapshot(std::uint64_t n);
  void print_summary() const;

  SimOptions options_;
  dds::Participant participant_;
  dds::TypedWriter<causal_twin::ConditionVectorPubSubType> conditions_;
  InterventionInbox interventions_;  // approvals whose writer's grant names their group
  std::vector<Group> groups_;
  std::vector<std::string> channel_names_;
  std::set<std::string> seen_requests_;  // an intervention instance re-sent (transient local) is applied once
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::uint64_t sent_ = 0, lost_ = 0, applied_ = 0, refused_ = 0, other_groups_ = 0;
};

}  // namespace causal::sim
