// causal-estimator parameters the integration tests write for the IMS feature tables: the sample level off and
// the condition level on the meanabs feature with fixed noise, so that factors come from the first condition
// vector on (nothing is learned first).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace causal::test {

// `graph` and `structure` are condition_level.instantaneous_graph and condition_level.structure (flow style).
inline std::string write_condition_level_params(
    const std::filesystem::path& file, const std::string& graph = "",
    const std::string& structure = "{calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}") {
  std::ofstream(file) << "sample_level:\n  enabled: false\n  lag_order: 1\n  include_self_lags: false\n"
                         "  instantaneous_graph: \"\"\n"
                         "  noise: {mode: fixed, q: 1.0e-6, r: 1.0e-2, p0: 1.0, calibration_samples: 4096}\n"
                         "  structure: {calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}\n"
                         "  publish_every: 1024\n  fixed_lag: 0\n"
                         "condition_level:\n  enabled: true\n  feature: meanabs\n  log_transform: true\n"
                         "  window_samples: 0\n  min_samples: 256\n  lag_order: 1\n  include_self_lags: true\n"
                         "  instantaneous_graph: \"" << graph << "\"\n"
                         "  noise: {mode: fixed, q: 1.0e-4, r: 1.0e-2, p0: 1.0, calibration_samples: 100}\n"
                         "  structure: " << structure << "\n"
                         "  publish_every: 1\n  fixed_lag: 0\n"
                         "health:\n  deadline_s: 30\n";
  return file.string();
}

}  // namespace causal::test
