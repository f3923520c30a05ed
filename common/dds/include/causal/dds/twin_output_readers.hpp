// The readers of everything the twin publishes for operators (condition vectors, causal factors, alarms,
// recommendations, asset status, prognoses, alarm action results), as causal-recorder and twin-web both read them: one reader per
// topic with its reader profile from qos.xml. Declare it before the EventLoop that waits on it (the loop,
// destroyed first, detaches the readers' conditions).
#pragma once

#include "causal/dds/event_loop.hpp"
#include "causal/dds/factor_sets.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <memory>
#include <string>

namespace causal::dds {

struct TwinOutputReaders {
  // status_profile: the asset-status reader profile (causal-recorder keeps the whole history, twin-web the
  // latest value per group).
  TwinOutputReaders(Participant& participant, const std::string& status_profile)
      : conditions(participant, topics::kConditionVector, profiles::kConditionVectorReader),
        factors(participant, topics::kCausalFactors, profiles::kCausalFactorsReader),
        factor_sets(make_factor_set_reader(participant)),
        alarms(participant, topics::kAlarm, profiles::kAlarmReader),
        recommendations(participant, topics::kRecommendation, profiles::kRecommendationReader),
        status(participant, topics::kAssetStatus, status_profile),
        prognoses(participant, topics::kPrognosis, profiles::kPrognosisReader),
        action_results(participant, topics::kAlarmActionResult, profiles::kAlarmActionResultReader) {}

  // Every reader wakes `loop`.
  void attach_to(EventLoop& loop) {
    loop.attach(conditions.get());
    loop.attach(factors.get());
    if (factor_sets) loop.attach(factor_sets->get());
    loop.attach(alarms.get());
    loop.attach(recommendations.get());
    loop.attach(status.get());
    loop.attach(prognoses.get());
    loop.attach(action_results.get());
  }

  TypedReader<causal_twin::ConditionVectorPubSubType> conditions;
  TypedReader<causal_twin::CausalFactorBatchPubSubType> factors;
  // The same factors, one message per input (factor_sets.hpp): unpacked in order. Null when DDS-Security does not
  // allow the topic (an identity issued before it existed).
  std::unique_ptr<FactorSetReader> factor_sets;
  TypedReader<causal_twin::AlarmPubSubType> alarms;
  TypedReader<causal_twin::RecommendationPubSubType> recommendations;
  TypedReader<causal_twin::AssetStatusPubSubType> status;
  TypedReader<causal_twin::PrognosisPubSubType> prognoses;
  TypedReader<causal_twin::AlarmActionResultPubSubType> action_results;  // operators' alarm actions, as applied
};

}  // namespace causal::dds
