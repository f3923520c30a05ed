#include "intervention_inbox.hpp"

#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <exception>

namespace causal::sim {

InterventionInbox::InterventionInbox(dds::Participant& participant)
    : participant_(participant),
      reader_(participant, dds::topics::kIntervention, dds::profiles::kInterventionReader),
      grants_(participant.directory(), "intervention", "approved intervention",
              "issue-identity.sh: an operator's grant names no partitions, or only those of --groups") {}

void InterventionInbox::take(const std::function<bool(const std::string& group)>& ours,
                             const std::function<void(const causal_twin::Intervention&)>& apply) {
  reader_.take_all([&](const causal_twin::Intervention& in, const auto& info) {
    if (!ours(in.asset_group()) || grants_.entitled(in.asset_group(), info.sample_identity.writer_guid())) {
      apply(in);
      return;
    }
    ++not_entitled_;
    spdlog::error("{}: intervention {} (approved by '{}') refused: its writer may not approve for this asset group "
                  "({} refused so far)", in.asset_group(), in.request_id(), in.approved_by(), not_entitled_);
  });
  for (auto& alarm : grants_.take_alarms()) raise(alarm);
}

void InterventionInbox::raise(causal_twin::Alarm& alarm) {
  spdlog::warn("HEALTH RAISED {}: {}", alarm.alarm_id(), alarm.reason());
  if (alarms_refused_) return;
  try {
    if (!alarms_) {
      alarms_ = std::make_unique<dds::TypedWriter<causal_twin::AlarmPubSubType>>(participant_, dds::topics::kAlarm,
                                                                                dds::profiles::kAlarmWriter);
    }
  } catch (const std::exception& e) {
    alarms_refused_ = true;
    spdlog::warn("HEALTH alarms of refused interventions are in this log only: {}", e.what());
    return;
  }
  const std::atomic<bool> never{false};
  if (alarms_->write(alarm, never, std::chrono::seconds(1)) != dds::WriteResult::Ok) {
    spdlog::error("HEALTH alarm {} could not be published within 1 s (it is in this log)", alarm.alarm_id());
  }
}

}  // namespace causal::sim
