// Whole-sequence passes for ONE outcome of the split filter (the batch estimators and the noise tuner run the
// outcomes one after the other, so the covariance history kept for RTS is N d_k^2, not N sum_k d_k^2).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "causal/noise_params.hpp"
#include "causal/svar_kalman_filter.hpp"
#include "causal/svar_layout.hpp"

namespace causal::detail {

// Status of every sample, exactly as SvarKalmanFilter::step would report it. Throws std::invalid_argument if
// samples.cols() != G or discontinuity is neither empty nor of size N.
std::vector<SampleStatus> classify_all(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                       const std::vector<bool>& discontinuity);

// Expands noise of size 1 to G entries and validates it.
std::vector<NoiseParams> expand_noise(const std::vector<NoiseParams>& noise, int channels);

struct OutcomeForward {
  // inputs
  const SvarLayout* layout = nullptr;
  int k = 0;
  const Eigen::MatrixXd* samples = nullptr;            // N x G
  const std::vector<SampleStatus>* status = nullptr;   // N
  NoiseParams noise;
  // optional outputs, nullptr = not wanted; "cols" = column-major with leading dimension N
  double* x_cols = nullptr;   // N x d filtered estimates x[n|n]
  double* sd_cols = nullptr;  // N x d sqrt(diag P[n|n])
  double* e_col = nullptr;    // N innovations (left untouched where no update)
  double* s_col = nullptr;    // N innovation variances (left untouched where no update)
  double* p_store = nullptr;  // N * d * d, P[n|n] column-major per sample
  // likelihood sums over updated samples (always filled)
  double sum_log_s = 0.0;
  double sum_e2_over_s = 0.0;
  std::int64_t updates = 0;
};

// Forward filter pass (same kernels and operation order as SvarKalmanFilter::step).
void run_outcome_forward(OutcomeForward& job);

// Rauch-Tung-Striebel backward pass for the random walk, in place: x_cols holds x[n|n] on entry and x[n|N-1]
// on exit; sd_cols receives sqrt(diag P[n|N-1]). p_store as filled by run_outcome_forward.
void run_outcome_rts(int d, Eigen::Index n_samples, double q, const double* p_store, double* x_cols,
                     double* sd_cols);

}  // namespace causal::detail
