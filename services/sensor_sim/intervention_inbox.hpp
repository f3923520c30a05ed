// sensor-sim's approved interventions in (causal_twin/intervention, plant mode): an approval is handed to the plant
// only when its writer's grant, as of the writer's first discovery, names the approval's asset group
// (dds/writer_grant_check.hpp, the check alarm-recommender applies to the same topic): an operator identity limited
// to some groups (issue-identity.sh --groups), or one that changed its partitions after matching, cannot move
// another group's plant. A refused approval is not applied, counted (not_entitled) and makes the exit code 4; its
// HEALTH group_not_entitled alarm (once per writer and group, naming the writer's participant) is logged
// ("HEALTH RAISED ...") and published on causal_twin/alarm when this identity may publish there (a sensor identity
// may not: then the journal holds it).
#pragma once

#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal_twinPubSubTypes.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace causal::sim {

class InterventionInbox {
 public:
  explicit InterventionInbox(dds::Participant& participant);
  // Every approval that arrived goes to `apply` when its group is not `ours` (the plant counts it as another's and
  // ignores it) or when its writer may approve for its group; the others are refused here.
  void take(const std::function<bool(const std::string& group)>& ours,
            const std::function<void(const causal_twin::Intervention&)>& apply);
  std::uint64_t not_entitled() const { return not_entitled_; }

 private:
  void raise(causal_twin::Alarm& alarm);

  dds::Participant& participant_;
  dds::TypedReader<causal_twin::InterventionPubSubType> reader_;
  dds::WriterGrantCheck grants_;
  std::unique_ptr<dds::TypedWriter<causal_twin::AlarmPubSubType>> alarms_;  // made at the first alarm
  bool alarms_refused_ = false;  // this identity may not publish alarms: the journal holds them
  std::uint64_t not_entitled_ = 0;
};

}  // namespace causal::sim
