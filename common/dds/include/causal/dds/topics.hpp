// Topic names and the QoS profile each endpoint is created from (profiles live in deploy/dds/qos.xml).
#pragma once

namespace causal::dds::topics {

inline constexpr const char* kVibrationFrame = "causal_twin/vibration_frame";
inline constexpr const char* kConditionVector = "causal_twin/condition_vector";  // estimator output
inline constexpr const char* kConditionInput = "causal_twin/condition_input";    // ready-made, to the estimator
inline constexpr const char* kCausalFactors = "causal_twin/causal_factors";
inline constexpr const char* kCausalFactorSets = "causal_twin/causal_factor_sets";  // one message per input
inline constexpr const char* kAlarm = "causal_twin/alarm";
inline constexpr const char* kRecommendation = "causal_twin/recommendation";
inline constexpr const char* kWhatIfRequest = "causal_twin/whatif_request";
inline constexpr const char* kWhatIfReply = "causal_twin/whatif_reply";
inline constexpr const char* kPrognosis = "causal_twin/prognosis";        // alarm-recommender: time to threshold
inline constexpr const char* kAssetStatus = "causal_twin/asset_status";   // alarm-recommender: one line per group
inline constexpr const char* kAlarmAction = "causal_twin/alarm_action";   // operator: acknowledge / shelve an alarm
inline constexpr const char* kAlarmActionResult = "causal_twin/alarm_action_result";  // alarm-recommender's answer
inline constexpr const char* kIntervention = "causal_twin/intervention";  // approvals only (causal-approve, twin-web)
inline constexpr const char* kInterventionOutcome = "causal_twin/intervention_outcome";  // alarm-recommender

}  // namespace causal::dds::topics

namespace causal::dds::profiles {

inline constexpr const char* kParticipant = "causal_twin_participant";
inline constexpr const char* kVibrationFrameWriter = "vibration_frame_writer";
inline constexpr const char* kVibrationFrameReader = "vibration_frame_reader";
inline constexpr const char* kConditionVectorWriter = "condition_vector_writer";
inline constexpr const char* kConditionVectorReader = "condition_vector_reader";
inline constexpr const char* kConditionInputWriter = "condition_input_writer";
inline constexpr const char* kConditionInputReader = "condition_input_reader";
inline constexpr const char* kCausalFactorsWriter = "causal_factors_writer";  // condition level
inline constexpr const char* kCausalFactorsSampleWriter = "causal_factors_sample_writer";  // sample level: deeper ring
inline constexpr const char* kCausalFactorsReader = "causal_factors_reader";
inline constexpr const char* kAlarmWriter = "alarm_writer";
inline constexpr const char* kAlarmReader = "alarm_reader";
inline constexpr const char* kRecommendationWriter = "recommendation_writer";
inline constexpr const char* kRecommendationReader = "recommendation_reader";
inline constexpr const char* kAssetStatusWriter = "asset_status_writer";  // transient-local, last value per group
inline constexpr const char* kAssetStatusReader = "asset_status_reader";
inline constexpr const char* kWhatIfWriter = "whatif_writer";
inline constexpr const char* kWhatIfReader = "whatif_reader";
inline constexpr const char* kPrognosisWriter = "prognosis_writer";
inline constexpr const char* kPrognosisReader = "prognosis_reader";
inline constexpr const char* kAlarmActionWriter = "alarm_action_writer";
inline constexpr const char* kAlarmActionReader = "alarm_action_reader";
inline constexpr const char* kAlarmActionResultWriter = "alarm_action_result_writer";
inline constexpr const char* kAlarmActionResultReader = "alarm_action_result_reader";
inline constexpr const char* kInterventionWriter = "intervention_writer";  // transient-local, bounded ring
inline constexpr const char* kInterventionReader = "intervention_reader";
inline constexpr const char* kInterventionOutcomeWriter = "intervention_outcome_writer";
inline constexpr const char* kInterventionOutcomeReader = "intervention_outcome_reader";

}  // namespace causal::dds::profiles
