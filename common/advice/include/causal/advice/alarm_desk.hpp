// The whole judging chain of one observation, without middleware: per asset group and time scale the alarm engine,
// its prognosis trends and its checkpoint (AlarmStateStore), the advisor's model of the condition level, the
// decision (advice policy) and the next level for every degradation event, the prognoses of the open alarms with
// their texts, the facts of the operator's status line, and the plain part of the intervention outcome check.
// It returns what happened (Judgement); alarm-recommender publishes and logs it, so the service is only its DDS
// edges (messages in, the judgement out) and the evaluation tools or a test can drive the same chain directly.
//
// Order per observation, kept from the store's contract (alarm_state_store.hpp): duplicate check -> engine ->
// checkpoint written -> (the caller) publish. judge() returns after the checkpoint, so everything it reports as
// an event is already on disk when the caller publishes it.
#pragma once

#include "causal/advice/advice_policy.hpp"
#include "causal/advice/advisor.hpp"
#include "causal/advice/alarm_state_store.hpp"
#include "causal/advice/recommender_params.hpp"
#include "causal/alarms/alarm_engine.hpp"
#include "causal/intervention/outcome_check.hpp"
#include "causal/prognosis/alarm_prognosis.hpp"
#include "causal/prognosis/channel_trends.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace causal::advice {

// Sample level (raw samples inside a frame) or condition level (one feature vector per snapshot). Sample first,
// as in the IDL: the engines are listed in this order at the end of a run.
enum class TimeScale { Sample = 0, Condition = 1 };
inline const char* to_string(TimeScale s) { return s == TimeScale::Sample ? "sample" : "condition"; }

// One observation to judge: the advisor's plain observation and the time scale it came from.
struct JudgedInput : ModelObservation {
  TimeScale time_scale = TimeScale::Condition;
};

// One prognosis line (one level of one channel with an open degradation alarm) at observation `index`.
struct PrognosisLine {
  prognosis::ChannelPrognosis prognosis;
  std::string channel_name;  // prognosis::channel_label
  std::string text;          // prognosis::prognosis_text
  std::uint64_t index = 0;
  std::int64_t time_ns = 0;
};

// One alarm event with what goes out with it.
struct EventJudgement {
  alarms::AlarmEvent event;
  // A degradation raise or escalation with the advice on: the decision (action and ranked items) is published on
  // the alarm and as recommendations at the event's own index (docs/advice.md "From alarm to action").
  bool advised = false;
  Decision decision;
  OrderTrust trust;            // as the recommendations carry it (source "untrusted" when the policy refuses it)
  double snapshot_hours = NAN;  // condition level: hours per snapshot (recommendation horizons); NaN otherwise
  // Condition level: the next level ahead and the time to it (the Alarm decision fields), with its text.
  bool has_next_level = false;
  prognosis::ChannelPrognosis next_level;
  std::string next_level_text;
};

// A stream's engine as it came back from its checkpoint (at start, or when its file appeared later).
struct Resumed {
  std::string asset_group;
  TimeScale time_scale = TimeScale::Condition;
  std::vector<std::string> channel_names;
  std::uint64_t observations = 0;
  std::size_t active_alarms = 0;
  std::vector<alarms::AlarmEvent> republish;  // last published event of every alarm id
  bool prognoses_judged = false;              // condition level with the prognosis on: `prognoses` is complete
  std::vector<PrognosisLine> prognoses;       // of the last observation the checkpoint holds
};

// What the operator's status line is built from (the group's engines after the observation). The pointers and the
// prognosis function refer into the desk: use them before its next judge() (the caller publishes at once).
struct StatusFacts {
  const alarms::AlarmEngine* condition = nullptr;  // the group's engines (null when that scale is not running)
  const alarms::AlarmEngine* sample = nullptr;
  bool stopped_now = false;  // the latest observation was gated as "not running"
  std::uint64_t index = 0;
  std::int64_t time_ns = 0;
  // The prognosis line for the worst open degradation alarm (AssetStatus.prognosis_text): "" when none is given.
  std::function<std::string(const alarms::AlarmEvent& worst)> prognosis;
};

struct Judgement {
  bool judged = false;     // false: the time scale is switched off, or a re-sent index (duplicate)
  bool duplicate = false;  // index not after the last one processed: dropped and counted (store().duplicates())
  // This observation opened its stream's engine: resumed from a checkpoint, or learning the baseline from the
  // first learning_observations.
  bool opened = false;
  bool resumed = false;
  Resumed resumed_from;
  int learning_observations = 0;
  // Interventions whose outcome check finished at this observation (condition level).
  std::vector<intervention::Outcome> finished_outcomes;
  // The what-if intervals' basis changed: the full per-outcome factor covariance (true) or standard deviations.
  bool covariance_changed = false;
  bool full_covariance = false;
  std::uint64_t observations_lost = 0;  // index jumps the engine saw (input lost upstream or while down)
  int trend_values_refused = 0;         // feature values the prognosis trends refused now ...
  std::uint64_t trend_values_refused_total = 0;  // ... and so far
  std::vector<std::string> checkpoint_errors;    // failed checkpoint writes to log (AlarmStateStore::take_errors)
  std::vector<EventJudgement> events;            // in the engine's order
  bool prognoses_judged = false;                 // condition level with the prognosis on: `prognoses` is complete
  std::vector<PrognosisLine> prognoses;
  StatusFacts status;
  bool baseline_learned = false;  // the baseline became ready at this observation
};

// An engine's counts for the end-of-run summary.
struct EngineSummary {
  std::string asset_group;
  TimeScale time_scale = TimeScale::Condition;
  std::uint64_t observations = 0, raised = 0, active = 0, discontinuities = 0, operating_changes = 0;
};

class AlarmDesk {
 public:
  // state_dir: the checkpoints (empty: none; AlarmStateStore throws std::invalid_argument for an unusable one).
  AlarmDesk(RecommenderParams params, std::string state_dir);

  // Every checkpoint in the state directory, restored before any data arrives (in file order): the caller
  // publishes their alarms and prognoses again. The stream's names are compared at its first observation.
  std::vector<Resumed> restore();
  // Judges one observation. Throws estimation::StateError naming the file when a checkpoint does not fit the
  // stream (other channels or factors): restarting silently would re-learn the baseline and reuse alarm ids.
  Judgement judge(const JudgedInput& input);
  // The causal-order trust of a group's condition-level factors (the advice policy's lever claims).
  void set_order_trust(const std::string& asset_group, const OrderTrust& trust) { order_trust_[asset_group] = trust; }

  Advisor& advisor() { return advisor_; }
  const Advisor& advisor() const { return advisor_; }
  intervention::OutcomeCheck& outcome_check() { return check_; }
  AlarmStateStore& store() { return store_; }
  std::vector<EngineSummary> summaries() const;

 private:
  struct EngineState {
    std::unique_ptr<alarms::AlarmEngine> engine;
    std::unique_ptr<prognosis::ChannelTrends> trends;  // degradation trend per channel (condition level)
    std::vector<std::string> channel_names;
    bool baseline_logged = false;
    int full_covariance = -1;  // last reported interval basis: -1 none yet, 0 diagonal, 1 full blocks
    std::uint64_t raised = 0;
    bool unverified = false;  // restored at start from its checkpoint: the stream's names are not compared yet
  };
  using Key = std::pair<std::string, int>;  // asset group, TimeScale

  bool enabled(TimeScale s) const { return s == TimeScale::Sample ? params_.sample_enabled : params_.condition_enabled; }
  alarms::AlarmParams params_for(bool sample_level) const;
  EngineState& engine_for(const JudgedInput& input, Judgement& out);
  void restored(const std::string& asset_group, bool sample, const EngineState& st, Resumed& out) const;
  void model_step(const JudgedInput& input, EngineState& st, Judgement& out);
  void judge_event(const JudgedInput& input, EngineState& st, const alarms::AlarmEvent& e, Judgement& out);
  Decision decide_for(const JudgedInput& input, const EngineState& st, const alarms::AlarmEvent& e) const;
  std::vector<PrognosisLine> prognoses(const EngineState& st, std::uint64_t index, std::int64_t time_ns) const;
  std::string status_prognosis(const EngineState& st, const alarms::AlarmEvent& worst) const;
  StatusFacts status_facts(const JudgedInput& input, bool stopped_now);
  std::vector<intervention::Outcome> check_outcomes(const JudgedInput& input);
  intervention::Prediction predict(const intervention::InterventionPlan& plan) const;

  RecommenderParams params_;
  Advisor advisor_;
  AlarmStateStore store_;
  intervention::OutcomeCheck check_;
  std::map<Key, EngineState> engines_;
  std::map<std::string, OrderTrust> order_trust_;     // per asset group, from its condition-level factor batches
  std::map<std::string, bool> status_last_stopped_;  // the condition level's latest operating-state verdict
};

}  // namespace causal::advice
