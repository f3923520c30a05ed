// causal-estimator's parameters: one plain struct and one loader that rejects missing or invalid keys.
#pragma once

#include "causal/pipeline/asset_pipeline.hpp"

#include <string>

namespace causal::pipeline {

// Throws causal::config::ConfigError naming the file and key.
[[nodiscard]] pipeline::AssetPipelineParams load_estimator_params(const std::string& path);

// The `health:` section: how long an asset group's input (frames, condition inputs) may stay silent while
// its writer is alive before a HEALTH alarm is raised (0 = no deadline; a lost writer still raises one).
struct EstimatorHealthParams {
  double deadline_s = 30.0;
};
[[nodiscard]] EstimatorHealthParams load_estimator_health(const std::string& path);

// The `output:` section (optional; absent = the defaults): how the factors leave the estimator.
//   batch: one CausalFactorBatch message per batch on causal_twin/causal_factors (each input writes 1-2);
//   set:   one CausalFactorSet message per input (a frame, or a snapshot at condition level) holding its
//          batches in write order, on causal_twin/causal_factor_sets (one write instead of two per frame).
enum class FactorMessages { Batch, Set };
struct EstimatorOutputParams {
  FactorMessages factor_messages = FactorMessages::Batch;
};
[[nodiscard]] EstimatorOutputParams load_estimator_output(const std::string& path);

}  // namespace causal::pipeline
