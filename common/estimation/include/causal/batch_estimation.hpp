// Whole-record estimators: filter, Rauch-Tung-Striebel smoother and fixed-lag smoother.
//
// All take samples N x G (one row per sample), an optional discontinuity flag per sample (flag at n: sample n
// starts a new segment, see SvarKalmanFilter::step) and noise of size 1 or G. Rows of the outputs are
// per-sample; factor columns are outcome-major (SvarLayout::factor_names()). Throws std::invalid_argument on
// shape mismatches or invalid noise. Non-finite samples are not errors: they get status RejectedNonFinite.
//
// Memory: the filter and the fixed-lag smoother keep O(F) / O(L sum d_k^2) state besides the outputs; RTS
// keeps x[n|n], P[n|n] of one group of (up to) 4 equal-dimension outcomes at a time: N * 4 (d^2 + d) doubles
// (G=4, M=1: 168 doubles = 1.3 kB per sample, i.e. 1.3 GB for 10^6 samples) on top of the outputs.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "causal/noise_params.hpp"
#include "causal/svar_kalman_filter.hpp"
#include "causal/svar_layout.hpp"

namespace causal {

struct EstimationRun {                     // N samples, F = total_factors, G = channels
  Eigen::MatrixXd estimates;               // N x F
  Eigen::MatrixXd std_devs;                // N x F
  Eigen::MatrixXd innovations;             // N x G (NaN where no update)
  Eigen::MatrixXd innovation_variances;    // N x G (NaN where no update)
  std::vector<SampleStatus> status;        // N
  FilterCounters counters;
  // Filtered standard deviations reported as 0 because rounding left their variance <= 0 (ill-scaled data);
  // non-zero means those outcomes lost precision and should not be trusted.
  std::uint64_t clamped_variances = 0;
};

// Row n = x[n|n] (the prediction where sample n was not used); identical to stepping SvarKalmanFilter.
EstimationRun run_filter(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                         const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity = {});

// Row n = x[n|N-1] with its standard deviations (RTS with covariances). Innovations are the filter's.
// Cost: forward pass + one d_k x d_k Cholesky and three d_k^3 products per sample and outcome.
EstimationRun run_rts_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                               const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity = {});

// Row n = x[n|min(n+lag, N-1)]: the estimate of x[n] given data up to n+lag (fewer at the end of the record),
// as produced by the streaming FixedLagSmoother. lag >= 0 (0 = filter).
EstimationRun run_fixed_lag_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                                     const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                                     int lag);

}  // namespace causal
