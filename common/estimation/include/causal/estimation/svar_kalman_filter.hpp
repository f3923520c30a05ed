// Streaming Kalman filter for the time-varying SVAR factors (random-walk state, see svar_layout.hpp).
// This is the ONE filter recursion of the library: the batch filter and RTS smoother (batch_estimation.hpp),
// the fixed-lag smoother and the noise tuning all step this class.
//
// The stacked system x[n+1] = x[n] + w, y[n] = H[n] x[n] + eps with block-diagonal H[n] (row k holds outcome
// k's regressors in its own block), Q = diag(q_k I), R = diag(r_k) and block-diagonal P0 keeps P block-diagonal
// for ever, so it splits exactly into G independent filters, one per outcome, each with a scalar measurement.
// (The tests check this against a dense stacked filter.)
//
// Time convention: x[0] ~ N(0, p0 I) is the prior at the first sample. Every later sample first predicts
// (P += q I: time passes whether or not the sample can be used), then updates if it is usable. Warm-up and
// rejected samples therefore still grow P by q I; their estimate is the prediction.
//
// Cost per sample: O(sum_k d_k^2) with d_k = factor_count(k); no heap allocation after construction.
// Outcomes of equal dimension are updated four at a time in SIMD lanes; dimensions 1..14 use kernels with
// compile-time sizes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::estimation {

enum class SampleStatus {
  Updated,           // all outcomes updated with this sample
  WarmUp,            // finite, but fewer than M previous samples in this segment: only fills the lag history
  RejectedNonFinite  // some value is NaN/inf: no update, lag history restarts
};

const char* to_string(SampleStatus status);

struct FilterCounters {
  std::uint64_t updated = 0;
  std::uint64_t warm_up = 0;
  std::uint64_t rejected_non_finite = 0;
};

class FixedLagSmoother;
class StateWriter;
class StateReader;
namespace detail {
struct LanePlan;
struct FilterAccess;
}

class SvarKalmanFilter {
 public:
  // noise.size() must be 1 (shared by all outcomes) or G; throws std::invalid_argument otherwise or if any
  // NoiseParams is invalid (see validate_noise_params).
  SvarKalmanFilter(const SvarLayout& layout, std::vector<NoiseParams> noise);

  // y: G values. discontinuity = true: y does not follow the previous sample (e.g. a gap), so the lag history
  // restarts and this sample plus the next M-1 only fill it (WarmUp). Any non-finite y -> RejectedNonFinite,
  // counted, and the lag history restarts (a NaN cannot serve as a regressor later either).
  SampleStatus step(const double* y, bool discontinuity = false);

  double last_innovation(int k) const;           // e_k of the last Updated step (NaN before the first)
  double last_innovation_variance(int k) const;  // S_k of the last Updated step (NaN before the first)
  Eigen::VectorXd estimate(int k) const;         // x_k, factor_count(k) values
  Eigen::MatrixXd covariance(int k) const;       // P_k
  void estimates(double* out) const;             // all factors, outcome-major, total_factors() values
  void std_devs(double* out) const;              // sqrt(diag P), same order
  const FilterCounters& counters() const { return counters_; }
  std::uint64_t samples_seen() const { return steps_; }
  const SvarLayout& layout() const { return layout_; }
  const NoiseParams& noise(int k) const;
  // Changes q and r from the next step on; p0 is used by reset().
  void set_noise(int k, const NoiseParams& noise);
  // Back to the prior x = 0, P = p0 I, empty lag history, zero counters.
  void reset();

  // Checkpoint (state_archive.hpp), section "svar_kalman_filter". Saved: the model spec (restore checks it),
  // q, r, p0 of every outcome, the states x and covariances P as held (lane-interleaved, padding lanes
  // included, so a restored filter continues bit for bit), the lag window and its valid history, the last
  // innovations and their variances, the step count and the counters. Not saved: the scratch of the last
  // update (regressors, P h, per-lane innovations), which is rewritten before it is read. restore() throws
  // StateError for a checkpoint of another model or a damaged one, and then leaves the filter unchanged.
  void save(StateWriter& w) const;
  void restore(StateReader& r);

 private:
  friend class FixedLagSmoother;
  friend struct detail::FilterAccess;  // batch passes and noise tuning (src/filter_access.hpp)
  // Same as the public constructor with a given lane plan (noise tuning: one outcome replicated in 4 lanes).
  SvarKalmanFilter(const SvarLayout& layout, std::vector<NoiseParams> noise,
                   std::shared_ptr<const detail::LanePlan> plan);
  using UpdateFn = void (*)(SvarKalmanFilter&, int group);
  template <int D>
  struct Select;
  struct StepKernel;  // step() itself, compiled per instruction set (src/svar_kalman_filter.cpp)
  // The checkpoint's field list after the model spec (SaveFields / RestoreFields, state_fields.hpp).
  template <class IO, class Self>
  static void fields(IO io, Self& self);

  // Internals are "lane groups" of up to 4 outcomes of equal dimension updated together in SIMD lanes
  // (src/kernels.hpp, src/lane_plan.hpp); vectors/matrices are stored lane-interleaved.
  SvarLayout layout_;
  std::vector<NoiseParams> noise_;
  int g_;
  int m_;
  std::shared_ptr<const detail::LanePlan> plan_;
  std::vector<int> gather_;      // per lane-interleaved regressor: index into window_
  std::vector<int> y_index_;     // per group lane: index into window_ of the outcome's own y[n]
  std::vector<double> q_, r_;    // per group lane (padding: q = 0, r = 1)
  std::vector<double> x_, p_;    // lane-interleaved states and covariances
  std::vector<double> h_, u_;    // regressors and P[n|n-1] h of the last update, lane-interleaved
  std::vector<double> e_lane_, s_lane_;  // last innovation and variance per group lane
  std::vector<double> e_, s_;    // last innovation and variance per outcome
  std::vector<double> window_;   // (M+1) x G + 1: window_[l*G + j] = y_j[n-l]; last element is always 0
  std::vector<double> work_;     // scratch for the dynamic-size kernels
  std::vector<UpdateFn> update_fn_;  // per group
  int history_ = 0;              // valid samples in window_ rows 1..M (capped at M)
  std::uint64_t steps_ = 0;
  FilterCounters counters_;
};

}  // namespace causal::estimation
