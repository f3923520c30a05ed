// Whole-record estimators: filter, Rauch-Tung-Striebel smoother and fixed-lag smoother.
//
// All take samples N x G (one row per sample), an optional discontinuity flag per sample (flag at n: sample n
// starts a new segment, see SvarKalmanFilter::step) and noise of size 1 or G. Rows of the outputs are
// per-sample; factor columns are outcome-major (SvarLayout::factor_names()). Throws std::invalid_argument on
// shape mismatches or invalid noise. Non-finite samples are not errors: they get status RejectedNonFinite.
//
// All three step the one filter recursion (SvarKalmanFilter), so they equal the streaming filter exactly.
//
// Memory besides the outputs: the filter and the fixed-lag smoother keep O(F) / O(L sum d_k^2) state. RTS
// does not keep the filtered covariances of the whole record: the forward pass keeps a copy of the filter
// every kRtsBlock samples (a few kB each), and the backward pass recomputes one block of filtered states from
// its copy (kRtsBlock * sum_k (d_k^2 + d_k) doubles, lanes padded to 4), last block first, carrying the
// smoothed state across blocks: O(N / kRtsBlock + kRtsBlock * d^2) instead of O(N d^2), for one extra forward
// pass. Results are identical to smoothing from a full history. The outputs are 2 * F doubles per kept row
// (BatchOutput::every decimates them) plus a status and, unless switched off, 2 * G doubles (innovations)
// per sample.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::estimation {

// Samples per RTS block (see Memory above).
constexpr Eigen::Index kRtsBlock = 2048;

// Which estimates are kept. every = k keeps samples 0, k, 2k, ...: row i of estimates / std_devs is sample
// i * k (ceil(N / k) rows). Decimation does not change any kept value, only what is stored.
struct BatchOutput {
  Eigen::Index every = 1;    // >= 1
  bool innovations = true;   // false: innovations / innovation_variances are left 0 x G (saves 2 G doubles
                             // per sample when only the factors are wanted)
};

struct EstimationRun {                     // N samples, F = total_factors, G = channels
  Eigen::MatrixXd estimates;               // ceil(N / every) x F
  Eigen::MatrixXd std_devs;                // ceil(N / every) x F
  Eigen::MatrixXd innovations;             // N x G (NaN where no update); 0 x G if not wanted
  Eigen::MatrixXd innovation_variances;    // N x G (NaN where no update); 0 x G if not wanted
  std::vector<SampleStatus> status;        // N
  FilterCounters counters;
  // Standard deviations (filtered or smoothed) reported as 0 because rounding left their variance <= 0
  // (ill-scaled data); non-zero means those outcomes lost precision and should not be trusted.
  std::uint64_t clamped_variances = 0;
};

// Row n = x[n|n] (the prediction where sample n was not used); identical to stepping SvarKalmanFilter.
EstimationRun run_filter(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                         const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity = {},
                         const BatchOutput& output = {});

// Row n = x[n|N-1] with its standard deviations (RTS with covariances). Innovations are the filter's.
// Cost: two forward passes + one d_k x d_k Cholesky and three d_k^3 products per sample and outcome.
EstimationRun run_rts_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                               const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity = {},
                               const BatchOutput& output = {});

// Row n = x[n|min(n+lag, N-1)]: the estimate of x[n] given data up to n+lag (fewer at the end of the record),
// as produced by the streaming FixedLagSmoother. lag >= 0 (0 = filter).
EstimationRun run_fixed_lag_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                                     const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                                     int lag, const BatchOutput& output = {});

}  // namespace causal::estimation
