// Alarm events published by the engine (mirrors causal_twin::Alarm in idl/causal_twin.idl, except that
// channels are 0-based here; adapters add 1).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::alarms {

enum class Severity { Advisory = 0, Warning = 1, Critical = 2 };
enum class AlarmState { Raised, Escalated, Cleared };

// Detector kinds (AlarmEvent::kind). One alarm at most is active per (channel, kind).
namespace kind {
inline constexpr const char* kFeatureDrift = "feature_drift";      // condition feature above its baseline
inline constexpr const char* kInnovationRise = "innovation_rise";  // unexplained part rose: own behaviour
inline constexpr const char* kInnovationNis = "innovation_nis";    // model no longer fits the channel
inline constexpr const char* kFactorShift = "factor_shift";        // causal factors left their baseline
// Operating-change events (category kOperatingChange): a level re-baselined, not a fault.
inline constexpr const char* kOperatingChange = "operating_change";  // an abrupt step that settled
inline constexpr const char* kDiscontinuity = "discontinuity";      // re-baselined after a gap / restart
inline constexpr const char* kLevelStep = "level_step";  // one channel stepped and settled: followed, not confirmed
// Health events (category kHealth): the twin, not the machine.
inline constexpr const char* kInputLost = "input_lost";  // observations skipped by a consecutive source: lost on the way
}  // namespace kind

// What an event is about (Alarm.category in the IDL): the machine degrading, a change of operating state the
// engine re-baselined on (reported so a reader can tell them apart; never counted as a fault), or the twin's
// own health (input it never received).
namespace category {
inline constexpr const char* kDegradation = "degradation";
inline constexpr const char* kOperatingChange = "operating_change";
inline constexpr const char* kHealth = "health";  // the twin lost input (no channel: channel -1)
}  // namespace category

struct AlarmEvent {
  std::string alarm_id;            // "<asset_group>/<channel 1-based>/<kind>/<counter>", stable across
                                   // Raised -> Escalated* -> Cleared
  int channel = -1;                // 0-based channel the alarm is about
  Severity severity = Severity::Advisory;
  AlarmState state = AlarmState::Raised;
  std::string kind;                // one of causal::alarms::kind
  std::string category = category::kDegradation;  // one of causal::alarms::category
  std::int64_t raised_time_ns = 0;
  std::int64_t cleared_time_ns = 0;  // 0 while active
  std::uint64_t index = 0;         // observation index of the latest evidence
  std::uint64_t onset_index = 0;   // estimated start of the change (CUSUM change point)
  std::int64_t onset_time_ns = 0;
  int root_cause_channel = -1;     // 0-based channel whose own behaviour changed first, -1 unknown
  std::vector<std::string> factor_names;  // factors that moved most (explanation)
  std::vector<double> factor_baseline;    // their baseline (median over the baseline period)
  std::vector<double> factor_now;         // their current values
  double score = 0.0;              // detector statistic (CUSUM S, window-mean NIS, max |z| of factors)
  double threshold = 0.0;          // the raise threshold it is compared with
  std::string reason;              // plain-language explanation with numbers and UTC times
  // Confidence of the root-cause attribution in [0, 1]: the probability that the named root's own-change
  // evidence truly exceeds the runner-up's among the channels whose trouble began no later than the root's
  // (within onset_tolerance); 1 when no such channel has departed, 0 when the root is unknown.
  double root_cause_confidence = 0.0;
};

// The one spelling of the severities and states (alarms.csv, the live view, the metrics, causal-report):
// "advisory" | "warning" | "critical", "raised" | "escalated" | "cleared"; parse_severity is the inverse.
const char* to_string(Severity s);
const char* to_string(AlarmState s);
[[nodiscard]] std::optional<Severity> parse_severity(std::string_view text);

// Checkpoint of one event, every field (the engine keeps each alarm's latest event; services keep the last
// published one to republish after a restart). restore() throws estimation::StateError on a truncated or
// foreign section, or an unknown severity / state.
void save(estimation::StateWriter& out, const AlarmEvent& event);
void restore(estimation::StateReader& in, AlarmEvent& event);

}  // namespace causal::alarms
