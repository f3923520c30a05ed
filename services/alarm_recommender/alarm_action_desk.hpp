// alarm-recommender's alarm management desk (ISA-18.2): operators' actions in on causal_twin/alarm_action, one
// result per action (and per shelving that expired) out on causal_twin/alarm_action_result. The state machine and
// the health figures are common/alarm_management (middleware-free); this only adapts it to the DDS types, the wall
// clock and the metrics.
//
// With --state-dir DIR its state (acknowledgements, shelvings with their end, the health histories, the outcomes
// of recent request ids) is checkpointed to DIR/alarm_management.state (AlarmManager::save, a versioned section),
// written atomically after every change and before the message that shows it is published (as the engine
// checkpoint), and restored at start: after a kill -9 an acknowledged alarm is still acknowledged and a shelving
// still ends at its time.
//
// Actions come from operator identities (twin-web, causal-alarm-action): one is applied only when its writer's
// grant, as of the writer's first discovery, names the action's asset group (dds/writer_grant_check.hpp, as the
// what-if requests). A refused action is answered "refused" (not applied), counted (summary not_entitled=,
// alarm_actions_total{result="not_entitled"}), alarmed once per writer and group (HEALTH group_not_entitled, taken
// with take_health_alarms) and makes the exit code 4.
#pragma once

#include "causal/alarm_management/alarm_management.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace causal::recommender {

class AlarmActionDesk {
 public:
  // state_dir empty: no checkpoint. Otherwise restores DIR/alarm_management.state when it exists; throws
  // estimation::StateError naming the file when it cannot be used (the operator moves it away to start over).
  AlarmActionDesk(dds::Participant& participant, const std::string& state_dir);
  dds::TypedReader<causal_twin::AlarmActionPubSubType>& reader() { return actions_; }

  // Before an alarm message is written: its event goes into the state, and its acknowledged / shelved flags come
  // out of it (a shelved source's events are still published and recorded, flagged).
  // republished: the message is the engine checkpoint's last event, published again after a restart (an alarm
  // already held keeps its acknowledgement).
  void on_publish(causal_twin::Alarm& msg, bool republished = false);
  // Takes the received actions, applies them at the wall clock, lifts shelvings that ran out; each gives one result
  // message. `changed` gets the asset groups whose state changed (their AssetStatus is published again).
  std::size_t poll(std::set<std::string>& changed, const std::atomic<bool>& stop);
  // AssetStatus's alarm management and health fields for its group at its data time (s.time_ns()).
  void fill(causal_twin::AssetStatus& s);
  void log_summary() const;
  // HEALTH group_not_entitled alarms raised by refused writers since the last call (the node publishes them).
  std::vector<causal_twin::Alarm> take_health_alarms() { return grants_.take_alarms(); }
  std::uint64_t not_entitled() const { return not_entitled_; }
  std::uint64_t result_write_failures() const { return result_failures_; }
  std::uint64_t checkpoint_failures() const { return save_failures_; }

 private:
  void publish(const causal_twin::AlarmActionResult& result, const std::atomic<bool>& stop);
  void count(const alarm_management::ActionOutcome& outcome, bool entitled);
  void restore();
  void save();  // a failure is counted and logged, never thrown (alarms keep flowing on a full disk)

  alarm_management::AlarmManager manager_;
  dds::TypedReader<causal_twin::AlarmActionPubSubType> actions_;
  dds::TypedWriter<causal_twin::AlarmActionResultPubSubType> results_;
  dds::WriterGrantCheck grants_;
  std::uint64_t not_entitled_ = 0;
  std::string state_file_;  // empty: no checkpoint
  std::uint64_t received_ = 0, unknown_kind_ = 0, results_published_ = 0, result_failures_ = 0;
  std::uint64_t saves_ = 0, save_failures_ = 0;
};

}  // namespace causal::recommender
