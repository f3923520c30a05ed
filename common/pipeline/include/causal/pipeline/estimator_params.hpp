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

}  // namespace causal::pipeline
