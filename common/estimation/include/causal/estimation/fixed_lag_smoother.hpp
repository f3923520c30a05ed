// Streaming fixed-lag smoother: after sample n it releases x[n-L | n] (data up to n) with its standard
// deviations, L = lag.
//
// Method: the filter state x[n] is augmented with the lagged states x[n-1..n-L]. For the random walk the
// augmented prediction just shifts them (x[n] becomes x[n-1] with cross-covariance P[n-1,n] = P[n-1|n-1]), and
// the scalar update y = h^T x[n] + eps with S = h^T P[n,n] h + r gives, for every lag i (Anderson & Moore,
// "Optimal Filtering", 1979, sec. 7.3):
//   g_i        = P[n-i,n] h / S
//   x[n-i]    += g_i e
//   P[n-i,n]  -= g_i (P[n,n] h)^T          (cross-covariance, d x d)
//   var[n-i]  -= S g_i .^2                 (diagonal of P[n-i,n-i], all that the output needs)
// The current block P[n,n] is the filter's own (Joseph form). Cost per sample and outcome: O(L d^2) time and
// L (d^2 + 2d) doubles of memory. The tests check the result against RTS run on data[0..n+L].
//
// Decimation: a service publishes one estimate every m samples, so only those samples need smoothing.
// With release_every = m only samples with (index + 1) % m == 0 enter the lag slots (each slot is then a
// fixed-point smoother of its own sample, the same equations): O(ceil(L / m) d^2) per sample instead of
// O(L d^2), with results identical to the full smoother at the released indices.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::estimation {

struct SmoothedSample {
  std::uint64_t index;       // 0-based sample index (counting every sample passed to step)
  Eigen::VectorXd estimates;  // all factors, outcome-major
  Eigen::VectorXd std_devs;
};

class FixedLagSmoother {
 public:
  // lag >= 0 (0 = plain filter), release_every >= 1 (see Decimation above); throws std::invalid_argument
  // otherwise or for invalid noise (see the filter).
  FixedLagSmoother(const SvarLayout& layout, std::vector<NoiseParams> noise, int lag, std::uint64_t release_every = 1);

  // Feeds sample y (same semantics as SvarKalmanFilter::step); returns the smoothed estimate of sample
  // (current index - lag) once available (and only for released indices when decimating).
  std::optional<SmoothedSample> step(const double* y, bool discontinuity = false);
  // Allocation-free form: returns true and writes total_factors() values to estimates and std_devs when a
  // smoothed sample is released.
  bool step_into(const double* y, bool discontinuity, std::uint64_t* index, double* estimates, double* std_devs);
  // Remaining samples at the end of the stream (each with all data seen so far). The smoother stays usable:
  // later samples are released with the full lag again and flushed indices are never released twice.
  std::vector<SmoothedSample> flush();

  const SvarKalmanFilter& filter() const { return filter_; }
  SampleStatus last_status() const { return last_status_; }
  int lag() const { return lag_; }
  std::uint64_t release_every() const { return release_every_; }
  bool released(std::uint64_t index) const { return (index + 1) % release_every_ == 0; }
  void reset();

  // Checkpoint (state_archive.hpp), section "fixed_lag_smoother". Saved: lag and release_every (restore
  // checks them), the filter (SvarKalmanFilter::save), the L ring slots of lagged states, cross-covariances
  // and variances as held, the ring position, the number of valid slots, the next index to release and the
  // last sample status. Restoring into a smoother of another model, lag or decimation throws StateError and
  // leaves it unchanged; a damaged checkpoint throws StateError too.
  void save(StateWriter& w) const;
  void restore(StateReader& r);

 private:
  template <int D>
  struct Select;
  using LagUpdateFn = void (*)(FixedLagSmoother&, int group);
  // The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);

  void shift_in_filter_state();
  int slot_pos(int i) const { return (head_ - (i - 1) + lag_) % lag_; }  // ring position of lag i (1..L)
  void write_lag(int i, double* estimates, double* std_devs) const;   // i = 0: the filter itself

  SvarKalmanFilter filter_;
  int lag_;
  std::uint64_t release_every_;
  // Per lane group of the filter (same lane-interleaved layout), L ring slots each:
  std::vector<double> xs_;   // group g at lag_ * x_off, slot s at + s * d * 4
  std::vector<double> pc_;   // cross-covariances P[n-i,n]: group g at lag_ * p_off, slot s at + s * d * d * 4
  std::vector<double> var_;  // diag P[n-i,n-i], laid out like xs_
  std::vector<double> work_;
  std::vector<LagUpdateFn> update_fn_;
  int head_ = 0;    // ring position of lag 1
  int active_ = 0;  // valid lagged slots (<= lag_)
  std::uint64_t next_release_ = 0;  // smallest index not yet released
  SampleStatus last_status_ = SampleStatus::WarmUp;
};

}  // namespace causal::estimation
