// causal-estimator's parameters: one plain struct and one loader that rejects missing or invalid keys.
#pragma once

#include "causal/pipeline/asset_pipeline.hpp"

#include <string>

namespace causal::estimator {

// Throws causal::config::ConfigError naming the file and key.
pipeline::AssetPipelineParams load_estimator_params(const std::string& path);

}  // namespace causal::estimator
