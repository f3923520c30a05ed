// The reference detector of the robustness suite: a plain robust-z alarm, per channel. Median and MAD of an early
// baseline window; z = (x - median) / (1.4826 MAD); an alarm when |z| > threshold for `persistence`
// consecutive snapshots. Only the first alarm of each channel is reported (no clearing rule): this is the
// bar the product must beat (earlier or equal on the failing bearing, no more false alarms).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

namespace causal::testing {

struct RobustZParams {
  std::size_t baseline_begin = 20;  // the product's shipped warm-up (alarm_params.hpp) ...
  std::size_t baseline_end = 140;   // ... and baseline (120 snapshots): both learn healthy on the same rows
  double threshold = 6.0;
  int persistence = 5;
};

struct RobustZChannel {
  double median = 0.0;
  double scale = 0.0;               // 1.4826 x MAD
  std::optional<std::size_t> first_alarm;  // row at which |z| > threshold had held for `persistence` rows
};

// values: N x G (rows in time order). Rows before baseline_end never alarm. Non-finite values break a run of
// exceedances (they neither count nor alarm). Throws std::invalid_argument when the baseline window does not
// fit or a channel's MAD is 0 (a constant channel has no scale to judge it by).
std::vector<RobustZChannel> robust_z_first_alarms(const Eigen::MatrixXd& values, const RobustZParams& params = {});

}  // namespace causal::testing
