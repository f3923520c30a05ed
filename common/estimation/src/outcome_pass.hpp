// Whole-sequence passes for ONE lane group (up to 4 outcomes of equal dimension, see lane_plan.hpp). The batch
// estimators run the groups one after the other, so the history kept for RTS is N * 4 * (d^2 + d) doubles for
// one group, not for the whole model.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "causal/noise_params.hpp"
#include "causal/svar_kalman_filter.hpp"
#include "causal/svar_layout.hpp"
#include "lane_plan.hpp"

namespace causal::detail {

// Status of every sample, exactly as SvarKalmanFilter::step would report it. Throws std::invalid_argument if
// samples.cols() != G or discontinuity is neither empty nor of size N.
std::vector<SampleStatus> classify_all(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                       const std::vector<bool>& discontinuity);

// Expands noise of size 1 to G entries and validates it.
std::vector<NoiseParams> expand_noise(const std::vector<NoiseParams>& noise, int channels);

struct GroupForward {
  // inputs
  const SvarLayout* layout = nullptr;
  const LaneGroup* group = nullptr;
  const Eigen::MatrixXd* samples = nullptr;           // N x G
  const std::vector<SampleStatus>* status = nullptr;  // N
  std::array<NoiseParams, kLanes> noise{};            // per lane (padding lanes are ignored)
  bool likelihood = false;                            // accumulate the sums below (costs a log per update)
  // optional outputs per lane, nullptr = not wanted; "cols" = column-major with leading dimension N
  std::array<double*, kLanes> x_cols{};   // N x d filtered estimates x[n|n]
  std::array<double*, kLanes> sd_cols{};  // N x d sqrt(diag P[n|n])
  std::array<double*, kLanes> e_col{};    // N innovations (left untouched where no update)
  std::array<double*, kLanes> s_col{};    // N innovation variances (left untouched where no update)
  double* store = nullptr;  // N * (d*d + d) * 4 doubles: P[n|n] then x[n|n], lane-interleaved, per sample
  // likelihood sums per lane over the updated samples
  std::array<double, kLanes> sum_log_s{};
  std::array<double, kLanes> sum_e2_over_s{};
  std::int64_t updates = 0;
  std::int64_t clamped_variances = 0;  // sd outputs whose variance was <= 0 (rounding) and were reported as 0
};

inline std::size_t store_doubles_per_sample(int d) {
  return static_cast<std::size_t>(d) * (d + 1) * kLanes;
}

// Forward filter pass (same kernels and operation order as SvarKalmanFilter::step).
void run_group_forward(GroupForward& job);

// Rauch-Tung-Striebel backward pass over `store` (filled by run_group_forward); writes x[n|N-1] to x_cols and
// sqrt(diag P[n|N-1]) to sd_cols for the real lanes.
void run_group_rts(const LaneGroup& group, Eigen::Index n_samples, const std::array<double, kLanes>& q,
                   const double* store, const std::array<double*, kLanes>& x_cols,
                   const std::array<double*, kLanes>& sd_cols);

}  // namespace causal::detail
