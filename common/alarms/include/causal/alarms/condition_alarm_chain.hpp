// The condition-level alarm chain without DDS: exactly what causal-estimator and alarm-recommender do with
// one asset group's condition vectors, in one process. Each vector goes through the estimator's
// AssetPipeline (input screen, structure calibration, centring, learned causal order, Kalman filter:
// common/pipeline), its filter reports are turned into observations by the recommender's rule
// (observation_from_outcomes, joined with the condition vector of the same time, as the recommender joins
// the condition_vector topic), and the AlarmEngine judges them. causal-alarm-eval and the offline tests
// run this chain, so what they report is what the plant sees (the services differ only by transport).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/pipeline/asset_pipeline.hpp"

namespace causal::alarms {

struct ChainOutput {
  std::vector<AlarmEvent> events;           // in the order the engine produced them
  std::uint64_t observations = 0;           // observations the engine judged
};

class ConditionAlarmChain {
 public:
  // estimator: causal-estimator's parameters (load_estimator_params); only the condition level is run.
  // alarms: alarm-recommender's condition-level parameters. Throws std::invalid_argument when either is
  // invalid or channel_names is empty.
  ConditionAlarmChain(std::string asset_group, std::vector<std::string> channel_names,
                      pipeline::AssetPipelineParams estimator, AlarmParams alarms);
  ~ConditionAlarmChain();
  ConditionAlarmChain(ConditionAlarmChain&&) noexcept;
  ConditionAlarmChain& operator=(ConditionAlarmChain&&) noexcept;

  // One ready-made condition vector, as causal-estimator receives it on condition_input (feature value
  // per channel, the source's snapshot index, its discontinuity flag and time). Returns false (nothing
  // fed, `problem` says why) when the estimator would refuse it.
  bool feed(const Eigen::VectorXd& values, std::uint64_t snapshot_index, bool discontinuity, std::int64_t time_ns,
            ChainOutput& out, std::string* problem = nullptr);
  // End of the stream: the estimator's last reports (a calibration window still filling is learned on
  // what it holds) go through the engine.
  void finish(ChainOutput& out);

  // Called with every observation the engine is fed, in order (tests replaying the stream). Empty = not called.
  std::function<void(const Observation&)> on_observation;

  const pipeline::AssetPipeline& estimator() const;
  const AlarmEngine* engine() const;  // null until the first complete set of filter reports
  const std::vector<std::string>& factor_names() const;  // empty until then

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace causal::alarms
