// The condition level of the shipped estimator.yaml for an IMS asset group (meanabs, VAR(1) with self lags,
// fixed noise, fixed lag 6; centre + VAR-LiNGAM order learned on 100 snapshots), shared by the pipeline
// checkpoint tests and the pipeline benchmark so that both measure the configuration a plant runs.
#pragma once

#include "causal/pipeline/asset_pipeline.hpp"

namespace causal::test {

inline void set_ims_condition_model(pipeline::AssetPipelineParams& p) {
  p.condition.feature = io::ConditionFeature::MeanAbs;
  p.condition_model.model.lag_order = 1;
  p.condition_model.model.include_self_lags = true;
  p.condition_model.noise.fixed = estimation::NoiseParams{1e-4, 1e-2, 1.0};
  p.condition_model.publish_every = 1;
  p.condition_model.fixed_lag = 6;
  p.condition_structure.calibration_samples = 100;
  p.condition_structure.centre = true;
  p.condition_structure.learn_order = true;
}

}  // namespace causal::test
