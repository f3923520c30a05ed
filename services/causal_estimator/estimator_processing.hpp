// causal-estimator, processing: one AssetPipeline per asset group (created, or restored from its checkpoint, at
// the group's first input), fed the input that admission let through, in order; its output goes to publishing.
// A fault in one group's estimation stops that group only (its input is refused from then on, counted).
#pragma once

#include "causal/pipeline/asset_pipeline.hpp"
#include "causal_twin.h"
#include "estimator_group.hpp"
#include "estimator_options.hpp"
#include "estimator_publishing.hpp"
#include "stage_trace.hpp"

#include <exception>
#include <map>
#include <memory>
#include <string>

namespace causal::estimator {

class EstimatorProcessing {
 public:
  EstimatorProcessing(const EstimatorOptions& options, pipeline::AssetPipelineParams params,
                      EstimatorPublisher& publisher);

  // The asset group's state: created, and restored from its checkpoint, at its first input. A checkpoint that
  // cannot be used refuses the group's input (GroupState::refused), the others carry on.
  GroupState& group(const std::string& name);
  std::map<std::string, GroupState>& groups() { return groups_; }
  const std::map<std::string, GroupState>& groups() const { return groups_; }

  // An admitted frame, in order (`gap`: input before it was lost; the lags restart). `trace`: the frame's stage
  // times, or null.
  void feed_frame(const causal_twin::VibrationFrame& frame, GroupState& a, bool gap,
                  const std::shared_ptr<StageTrace::Frame>& trace);
  // An admitted condition input, in order; the accepted vector goes on to the estimator's own topic.
  void feed_condition(const causal_twin::ConditionVector& in, GroupState& a);
  // At exit: each group's checkpoint (before the flush), then the pipeline's flush, published.
  void finish();

 private:
  // A fault in the estimation: this group stops, loudly (its input is refused from now on, counted).
  void fail(const std::string& name, GroupState& a, const std::exception& e, std::uint64_t snapshot,
            std::int64_t time_ns);
  void log_adjustments(const std::string& name, GroupState& a);  // once per group, after its first accepted input
  // The pipeline's check of one input: refused (counted in `refused`, logged, reported) or accepted (its
  // adjustments logged). `kind` and `number` name the input in the log.
  bool accepted(const std::string& name, GroupState& a, const pipeline::FrameCheck& check, std::uint64_t& refused,
                const char* kind, std::uint64_t number, std::uint64_t snapshot, std::int64_t time_ns);
  // Once per group, the first time its sample level runs in steady state (noise calibrated, its buffered window
  // replayed): the process's CPU and the frames fed so far, so that deploy/bench_scale.sh can take the CPU per
  // frame of the steady state (every group past its start-up) apart from the start-up.
  void log_startup_done(const std::string& name, GroupState& a);
  // Once each: the learned structure at both levels and the sample level's noise (tuned or fixed).
  void log_learned(const std::string& name, GroupState& a);
  void log_structure(const std::string& name, const GroupState& a, const char* level,
                     const pipeline::LearnedStructure* learned, bool& logged) const;

  const EstimatorOptions& options_;
  pipeline::AssetPipelineParams params_;
  EstimatorPublisher& publisher_;
  std::map<std::string, GroupState> groups_;
  std::uint64_t frames_fed_ = 0;  // frames accepted, all groups
  pipeline::PipelineOutput out_;
};

}  // namespace causal::estimator
