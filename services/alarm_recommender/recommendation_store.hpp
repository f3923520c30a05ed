// What alarm-recommender keeps of its published keep-last topics (kept_messages.hpp), per asset group:
//  * RecommendationStore: DIR/<group>.recommendations.state, last value per recommendation id. Without it a live
//    view or recorder that joined after a restart saw the open alarms with none of their advice.
//  * AlarmMessageStore: DIR/<group>.alarm_messages.state, the last Alarm message per open alarm id as published, with
//    its decision (action, next_level, hours_to_next_level*). The engine checkpoint restores the alarm events;
//    their decision is taken when they are published and was lost at a restart (republished alarms had an
//    empty action).
#pragma once

#include "causal_twinPubSubTypes.h"
#include "kept_messages.hpp"

namespace causal::recommender {

struct RecommendationTraits {
  static constexpr const char* kTag = "alarm_recommender_recommendations";
  static constexpr std::uint32_t kVersion = 1;
  static constexpr const char* kSuffix = ".recommendations.state";
  static constexpr const char* kWhat = "recommendation";
  static const std::string& id(const causal_twin::Recommendation& r) { return r.recommendation_id(); }
  static const std::string& group(const causal_twin::Recommendation& r) { return r.asset_group(); }
  static bool keep(const causal_twin::Recommendation&) { return true; }  // the topic keeps every one
};
using RecommendationStore =
    KeptMessages<causal_twin::Recommendation, causal_twin::RecommendationPubSubType, RecommendationTraits>;

struct AlarmMessageTraits {
  static constexpr const char* kTag = "alarm_recommender_alarm_messages";
  static constexpr std::uint32_t kVersion = 1;
  static constexpr const char* kSuffix = ".alarm_messages.state";
  static constexpr const char* kWhat = "alarm message";
  static const std::string& id(const causal_twin::Alarm& a) { return a.alarm_id(); }
  static const std::string& group(const causal_twin::Alarm& a) { return a.asset_group(); }
  // Open alarms only: a cleared one carries no decision, and the engine checkpoint republishes it as it is.
  static bool keep(const causal_twin::Alarm& a) { return a.state() != causal_twin::AlarmState::CLEARED; }
};
using AlarmMessageStore = KeptMessages<causal_twin::Alarm, causal_twin::AlarmPubSubType, AlarmMessageTraits>;

// Copies the decision fields of `kept` (the message last published for this alarm id) onto `rebuilt` (the same
// alarm's last event rebuilt from the engine checkpoint) when both describe the same event (state, severity,
// evidence index); false otherwise (the process died between the engine checkpoint and publishing).
bool restore_decision(const causal_twin::Alarm& kept, causal_twin::Alarm& rebuilt);

}  // namespace causal::recommender
