// alarm-recommender's DDS node: causal factors and condition vectors in; alarms (and, on a raised alarm,
// recommendations), prognoses and asset statuses out. The judging of every observation is the alarm desk
// (common/advice alarm_desk.hpp, no DDS); the node assembles its input and publishes and logs its judgement
// (recommender_node.cpp).
#pragma once

#include "advice_names.hpp"
#include "alarm_action_desk.hpp"
#include "asset_status.hpp"
#include "intervention_desk.hpp"
#include "observation_assembler.hpp"
#include "open_alarm_metrics.hpp"
#include "prognosis_metrics.hpp"
#include "recommendation_store.hpp"

#include "causal/advice/alarm_desk.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal/dds/factor_sets.hpp"
#include "causal/dds/health_watch.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal_twinPubSubTypes.h"

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace causal::recommender {

struct RecommenderOptions {
  dds::CommonOptions dds;
  std::string params_file;
  double idle_exit_s = 0.0;
  double max_runtime_s = 0.0;
  std::string state_dir;  // checkpoints of the alarm engines (empty: none), see alarm_state_store.hpp
  // Readers to wait for on every output topic before taking input ("NAME" or "NAME:COUNT"), e.g. the recorder:
  // the writers keep only the last 64 changes per key for late joiners, and a learning group changes at every
  // snapshot, so a historian that matches after that ring has turned over would miss the first ones.
  std::vector<std::string> wait_for;
  double wait_timeout_s = 30.0;
};

class RecommenderNode {
 public:
  RecommenderNode(RecommenderOptions options, RecommenderParams params);
  int run();
  // --wait-for: 0 when every named reader matched (or none asked), 3 when one did not in time.
  int wait_for_readers();
  // Logs "caught up: ..." once when every source of causal factors and condition vectors has left (sources_gone,
  // read before this poll's take), the poll took no input (taken == 0: all taken before is judged) and every
  // matched reader acknowledged all alarms, recommendations, prognoses and statuses published; again after a
  // source came back and left (recommender_wait.cpp). Tests and scripts wait for it, not for a guessed time.
  void note_caught_up(bool sources_gone, std::size_t taken);
  void stop() { loop_.stop(); }

 private:
  // Judges `ready` in order; after each observation take_more() takes what the readers got meanwhile (input,
  // what-if requests, alarm actions).
  void handle(std::vector<AssembledObservation>& ready, const std::function<void()>& take_more);
  // One observation: judged by the desk, its judgement published (the DDS edges only).
  void observe(AssembledObservation& a);
  // The judgement of `a` published and logged in the order the chain produced it (recommender_node.cpp).
  void publish_judgement(const AssembledObservation& a, const advice::Judgement& j);
  // A stream resumed from its checkpoint: logged, its alarms (with their kept decisions) and prognoses published.
  void publish_resumed(const advice::Resumed& r);
  // An alarm event with its decision's action (Alarm.action; "" unless advised) and, at condition level, the time
  // to the next level (the Alarm decision fields).
  void publish_event(const AssembledObservation& a, const advice::EventJudgement& j);
  void recommend(const AssembledObservation& a, const advice::EventJudgement& j);
  // One Prognosis per level for every channel with an open degradation alarm (condition level).
  void publish_prognoses(const std::string& asset_group, const std::vector<advice::PrognosisLine>& lines);
  void answer(const causal_twin::WhatIfRequest& request);
  // Takes the what-if requests: answered when their writer's grant names their group, else refused
  // (recommender_whatif.cpp). Returns the number taken.
  std::size_t take_whatif_requests();
  // What-if requests and alarm actions, taken after every observation judged (handle) and between polls: a backlog
  // judged in one batch (hundreds of observations after a slow stretch) never keeps an operator waiting for more
  // than one observation. Returns the number taken.
  std::size_t take_operator_requests() { return take_whatif_requests() + poll_alarm_actions(); }
  void publish_health_alarm(causal_twin::Alarm& alarm);  // logged and written on causal_twin/alarm
  void log_whatif_summary() const;
  void publish_health();  // HEALTH alarms of silent or lost factor streams (HealthWatch), raised and cleared
  // At start: every alarm engine and recommendation in --state-dir restored and their last messages published
  // again, before any data arrives (readers that join after a restart see the open alarms and their advice).
  void restore_checkpoints();
  void republish(const std::string& asset_group, const std::vector<std::string>& channel_names,
                 const std::vector<alarms::AlarmEvent>& events);
  // AssetStatus of the group after an observation: published when it changed.
  void publish_status(const AssembledObservation& a, const advice::StatusFacts& facts);
  // Operators' alarm actions and expired shelvings (recommender_alarm_actions.cpp): applied, answered, and the
  // changed groups' AssetStatus published again.
  std::size_t poll_alarm_actions();
  // Every causal factor message the readers hold, batches and sets alike, into the assembler (appended to `into`).
  std::size_t take_factors(std::vector<AssembledObservation>& into);

  RecommenderOptions options_;
  RecommenderParams params_;
  dds::Participant participant_;
  dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> factors_;
  // The same factors, one message per input, unpacked in order (factor_sets.hpp); null when DDS-Security does not
  // allow the topic.
  std::unique_ptr<dds::FactorSetReader> factor_sets_;
  dds::FactorSetCounts factor_set_counts_;
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> conditions_;
  dds::TypedReader<causal_twin::WhatIfRequestPubSubType> whatif_requests_;
  dds::TypedWriter<causal_twin::AlarmPubSubType> alarms_;
  dds::TypedWriter<causal_twin::RecommendationPubSubType> recommendations_;
  dds::TypedWriter<causal_twin::WhatIfReplyPubSubType> whatif_replies_;
  dds::TypedWriter<causal_twin::AssetStatusPubSubType> status_writer_;
  AssetStatusBoard status_;
  std::uint64_t statuses_published_ = 0, status_write_failures_ = 0;
  dds::TypedWriter<causal_twin::PrognosisPubSubType> prognoses_;
  AlarmActionDesk action_desk_;  // acknowledge / shelve (ISA-18.2): its reader is attached to loop_
  advice::AlarmDesk desk_;          // the judging chain: engines, checkpoints, advice, prognoses (alarm_desk.hpp)
  InterventionDesk interventions_;  // approved interventions in, their checked outcomes out (intervention_desk.hpp)
  dds::EventLoop loop_;  // after the readers: detaches their conditions first
  ObservationAssembler assembler_;
  RecommendationStore recommendation_store_;
  AlarmMessageStore alarm_message_store_;  // each alarm as published, with its decision (republished after a restart)
  std::uint64_t decisions_not_kept_ = 0;   // republished alarms whose decision was not kept (died in between)
  dds::HealthWatch health_;
  causal_twin::Alarm alarm_msg_;
  causal_twin::Prognosis prognosis_msg_;
  std::uint64_t prognoses_published_ = 0, prognosis_write_failures_ = 0;
  std::uint64_t invalid_msgs_ = 0, alarms_published_ = 0, recommendations_published_ = 0;
  // Observations an engine of this process saw skipped (index jumps of a consecutive source: input lost upstream
  // or while this process was down; the engine's HEALTH event input_lost names them). Metric
  // recommender_observations_lost_total{asset_group, time_scale}; lost= in the summary.
  std::uint64_t observations_lost_ = 0;
  std::uint64_t events_advised_ = 0, events_act_on_asset_ = 0, events_upstream_lever_ = 0;
  OpenAlarmMetrics open_alarms_;  // causal_twin_alarms_open{asset_group, category, severity}
  PrognosisMetrics prognosis_metrics_;  // causal_twin_prognosis_time_to_level_seconds{...}
  std::uint64_t factors_received_ = 0, conditions_received_ = 0;
  std::uint64_t observations_judged_ = 0;
  bool sources_seen_ = false, caught_up_logged_ = false;  // note_caught_up
  dds::WriterGrantCheck whatif_grants_{
      participant_.directory(), "whatif", "what-if request",
      "issue-identity.sh: an operator's grant names no partitions, or only those of --groups"};
  std::uint64_t whatif_received_ = 0, whatif_not_entitled_ = 0;
};

}  // namespace causal::recommender
