// alarm-recommender's side of the closed prescriptive loop: approved interventions in (causal_twin/intervention),
// their checked outcomes out (causal_twin/intervention_outcome). The check itself is common/intervention
// (outcome_check.hpp, no DDS), owned and fed by the alarm desk (advice::AlarmDesk: every condition-level
// observation, the frozen what-if from the advisor's model as of the snapshot before the start); this adapter
// hands it the approvals and publishes the outcomes the desk's judgement reports finished. Lever trust learned
// from the outcomes withdraws a lever's claim (lever_claimed) when its outcomes miss.
//
// Approvals come from operator identities (causal-approve, twin-web): one is taken only when its writer's grant,
// as of the writer's first discovery, names the approval's asset group (dds/writer_grant_check.hpp, as the what-if
// requests and alarm actions). A refused approval is not checked, counted (not_entitled), alarmed once per writer
// and group (HEALTH group_not_entitled, taken with take_health_alarms) and makes the exit code 4.
#pragma once

#include "advice_names.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal/intervention/outcome_check.hpp"
#include "causal_twinPubSubTypes.h"

#include <map>
#include <string>
#include <vector>

namespace causal::recommender {

class InterventionDesk {
 public:
  // check: the alarm desk's outcome check (it outlives this desk).
  InterventionDesk(dds::Participant& participant, intervention::OutcomeCheck& check);
  // The loop that wakes on approvals and whose stop flag bounds the outcome writes (call once, before run).
  void attach(dds::EventLoop& loop);
  // Approvals that arrived (each request id once); returns the number of messages taken.
  std::size_t take();
  // The outcomes the alarm desk's check finished at an observation of `group` (its channel names name them).
  void publish_finished(const std::string& group, const std::vector<std::string>& channel_names,
                        const std::vector<intervention::Outcome>& outcomes);
  // At exit: every intervention still open is published as "no_data" (never dropped silently).
  void finish();
  // Whether lever `lever` on `target` (0-based) of `group` may still be claimed, and the reason when not.
  bool lever_claimed(const std::string& group, int lever, int target, std::string& why) const;
  // HEALTH group_not_entitled alarms raised by refused writers since the last call (the node publishes them).
  std::vector<causal_twin::Alarm> take_health_alarms() { return grants_.take_alarms(); }
  std::uint64_t not_entitled() const { return not_entitled_; }

 private:
  void publish(const intervention::Outcome& o);

  dds::Participant& participant_;
  dds::TypedReader<causal_twin::InterventionPubSubType> in_;
  dds::TypedWriter<causal_twin::InterventionOutcomePubSubType> out_;
  const std::atomic<bool>* stop_ = nullptr;
  std::atomic<bool> never_stopped_{false};
  intervention::OutcomeCheck& check_;
  dds::WriterGrantCheck grants_;
  std::uint64_t not_entitled_ = 0;
  std::map<std::string, std::vector<std::string>> channel_names_;  // per group, for the texts
  std::uint64_t approvals_ = 0, invalid_ = 0, published_ = 0, write_failures_ = 0;
};

// A lever recommendation (action_kind "upstream_lever") whose lever lost its claim through missed outcomes is
// published as not reliable, with the reason appended to its text: causal-approve refuses to approve it.
void withdraw_if_untrusted(const InterventionDesk& desk, causal_twin::Recommendation& msg);

}  // namespace causal::recommender
