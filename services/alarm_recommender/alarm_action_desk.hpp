// alarm-recommender's alarm management desk (ISA-18.2): operators' actions in on causal_twin/alarm_action, one
// result per action (and per shelving that expired) out on causal_twin/alarm_action_result. The state machine and
// the health figures are common/alarm_management (middleware-free); this only adapts it to the DDS types, the wall
// clock and the metrics.
#pragma once

#include "causal/alarm_management/alarm_management.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <cstdint>
#include <set>
#include <string>

namespace causal::recommender {

class AlarmActionDesk {
 public:
  explicit AlarmActionDesk(dds::Participant& participant);
  dds::TypedReader<causal_twin::AlarmActionPubSubType>& reader() { return actions_; }

  // Before an alarm message is written: its event goes into the state, and its acknowledged / shelved flags come
  // out of it (a shelved source's events are still published and recorded, flagged).
  void on_publish(causal_twin::Alarm& msg);
  // Takes the received actions, applies them at the wall clock, lifts shelvings that ran out; each gives one result
  // message. `changed` gets the asset groups whose state changed (their AssetStatus is published again).
  std::size_t poll(std::set<std::string>& changed, const std::atomic<bool>& stop);
  // AssetStatus's alarm management and health fields for its group at its data time (s.time_ns()).
  void fill(causal_twin::AssetStatus& s);
  void log_summary() const;
  std::uint64_t result_write_failures() const { return result_failures_; }

 private:
  void publish(const causal_twin::AlarmActionResult& result, const std::atomic<bool>& stop);
  void count(const alarm_management::ActionOutcome& outcome);

  alarm_management::AlarmManager manager_;
  dds::TypedReader<causal_twin::AlarmActionPubSubType> actions_;
  dds::TypedWriter<causal_twin::AlarmActionResultPubSubType> results_;
  std::uint64_t received_ = 0, unknown_kind_ = 0, results_published_ = 0, result_failures_ = 0;
};

}  // namespace causal::recommender
