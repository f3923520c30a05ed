// Automatic q, r for one outcome by maximising the innovation (prediction-error) log-likelihood
//   log L(q, r) = -1/2 sum_n [ log(2 pi S_n) + e_n^2 / S_n ]     over the Updated samples of the window
// (Harvey, "Forecasting, Structural Time Series Models and the Kalman Filter", 1989, sec. 3.4).
//
// Method (concentrated likelihood + 1-D search):
//  * Scaling: with Q = lambda r I, R = r, P0 = pi r I every covariance of the filter is r times that of the
//    filter run with (lambda, 1, pi): the innovations e_n do not depend on r and S_n = r s_n. For fixed
//    (lambda, pi) the maximiser in r is closed form, r_hat = (1/N) sum e_n^2 / s_n, and the concentrated
//    log-likelihood is  -1/2 [ N log(2 pi r_hat) + sum log s_n + N ].
//  * P0: options.p0 is ABSOLUTE (factor units, as in NoiseParams), so pi = p0 / r depends on r and the scaling
//    is exact only at the right r. Treatment: fixed-point rounds. Round 1 uses pi = p0 / r_ref with r_ref the
//    mean square of y_k over the window; each round searches lambda with pi fixed, then sets r_ref = r_hat.
//    Rounds stop when r_hat changes by < 0.1 % and log10(lambda) by < 0.05. P0 only shapes the first few
//    updates, so this converges in 2-3 rounds. The returned NoiseParams has p0 = options.p0 and the reported
//    log_likelihood is the exact one of the returned (q, r, p0) (one extra pass).
//  * Search over log10(lambda) in [log10_ratio_min, log10_ratio_max]: the filter runs 4 candidate ratios at
//    once in SIMD lanes, so each pass evaluates 4 points. Round 1 scans a 1-decade grid, then a 4-point
//    bracketing search (4 equally spaced interior points per pass, bracket shrunk to +-1 spacing around the
//    best: x 0.4 per pass) in +-1 decade around the best grid point to 0.01 decade; later rounds search
//    +-0.5 decade around the previous optimum.
// Cost: one filter pass of outcome k over the window per 4 evaluations, O(N d_k^2); typically ~20 passes
// (e.g. N = 5000, d = 6: a few ms). max_evaluations caps the passes (converged = false if it stops the search).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::estimation {

struct NoiseTuningOptions {
  double p0 = 1.0;                 // absolute initial state variance used for tuning and returned
  double log10_ratio_min = -12;    // search range of log10(q / r)
  double log10_ratio_max = 0;
  int max_evaluations = 60;        // filter passes (4 candidates each), including the final exact one; >= 8
};

struct NoiseTuningResult {
  NoiseParams noise;               // q = lambda_hat r_hat, r = r_hat, p0 = options.p0
  double log_likelihood = 0.0;     // exact innovation log-likelihood of `noise` on the window
  int evaluations = 0;             // filter passes used (each evaluates up to 4 candidates)
  bool converged = false;          // search tolerance and r fixed point reached within max_evaluations
  std::string message;             // human-readable summary (and why not converged / limit hit)
  bool at_range_limit = false;     // optimum within 0.05 decade of log10_ratio_min or _max
  long updates = 0;                // Updated samples in the window (terms of the likelihood)
  // `noise` is a usable tuned value: finite q >= 0, r > 0 and a finite log-likelihood. False: the window
  // could not be tuned (too few samples, a dead outcome, absurd values, no candidate with a finite
  // likelihood); keep the configured noise, `message` says why. Never throws for such data.
  bool usable = false;
  int failed_candidates = 0;       // candidates whose likelihood was not finite (never taken as the optimum)
};

// Tunes outcome k on the calibration window `samples` (N x G, discontinuity empty or N flags). Throws
// std::invalid_argument for bad shapes / options; data never throws: too few usable samples (< 2 d_k + 10), an
// outcome that is identically zero, a non-finite mean square or no finite likelihood give usable = false,
// converged = false, NoiseParams{} (with p0 = options.p0) and an explanatory message.
NoiseTuningResult tune_noise(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                             const std::vector<bool>& discontinuity, const NoiseTuningOptions& options = {});

// tune_noise for every outcome; result[k] for outcome k.
std::vector<NoiseTuningResult> tune_noise_all(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                              const std::vector<bool>& discontinuity,
                                              const NoiseTuningOptions& options = {});

// Exact innovation log-likelihood of outcome k under `noise` (one filter pass). Returns -inf when no sample
// is usable; *updates (optional) receives the number of terms.
double innovation_log_likelihood(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                                 const std::vector<bool>& discontinuity, const NoiseParams& noise,
                                 long* updates = nullptr);

}  // namespace causal::estimation
