// causal-estimator's DDS node: frames (and ready-made condition vectors) in; causal factors and condition
// vectors out. Three roles, one class each: admission (the readers and the screen of every input,
// estimator_admission.hpp), processing (one AssetPipeline per asset group, estimator_processing.hpp) and
// publishing (the writers, checkpoints, alarms, estimator_publishing.hpp); the node wires them to the participant
// and the event loop and runs them. A shard (--shards FILE --shard NAME, or --shard-index/--shard-count)
// subscribes to content-filtered frames and condition inputs: it receives only its own asset groups
// (dds/asset_group_filter.hpp), so N estimators divide the work.
#pragma once

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/pipeline/asset_pipeline.hpp"
#include "estimator_admission.hpp"
#include "estimator_options.hpp"
#include "estimator_processing.hpp"
#include "estimator_publishing.hpp"
#include "stage_trace.hpp"

namespace causal::estimator {

class EstimatorNode {
 public:
  EstimatorNode(EstimatorOptions options, pipeline::AssetPipelineParams params);
  // Exit codes: 0 done, 3 the named readers never came, 4 data was lost or refused on the way (see the summary).
  int run();
  void stop() { loop_.stop(); }

 private:
  int finish_all();  // publishes what is left, drains, logs the summary; returns the exit code
  int log_summary() const;  // the summary of finish_all (estimator_summary.cpp); returns the exit code

  EstimatorOptions options_;
  dds::Participant participant_;
  StageTrace trace_;
  // Declaration order is destruction order reversed: the loop detaches the readers' conditions before the
  // readers (admission) go; the publisher's outbound queue stops its drain thread before its writers go.
  EstimatorAdmission admission_;  // the readers first (as before the roles were split): then the writers
  dds::EventLoop loop_;
  EstimatorPublisher publisher_;
  EstimatorProcessing processing_;
};

}  // namespace causal::estimator
