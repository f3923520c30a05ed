// Small, dependency-free statistics used to design and run the alarm detectors:
// robust location/scale (median / MAD), Gaussian and chi-square quantiles, and the CUSUM
// average-run-length (ARL) approximation used to turn a target false-alarm rate into a threshold.
#pragma once

#include <cstddef>
#include <vector>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::alarms {

// Median of the finite values of `v` (NaN when there are none). Takes a copy: callers keep their order.
double median(std::vector<double> v);

// Robust location and scale of a baseline sample.
struct RobustStats {
  double location = 0.0;     // median
  double scale = 1.0;        // 1.4826 * MAD (consistent for sigma under a Gaussian), with fallbacks
  double lag1_autocorr = 0;  // sample lag-1 autocorrelation of the (time-ordered) sample, for diagnostics
  std::size_t count = 0;     // finite values used
  bool valid = false;        // false when fewer than 2 finite values were available
};

// Checkpoint of a learned baseline (the values themselves are not kept once the baseline is learned, so
// a restart must carry the estimate). restore() throws estimation::StateError on a truncated or foreign section.
void save(estimation::StateWriter& out, const RobustStats& stats);
void restore(estimation::StateReader& in, RobustStats& stats);

// Median and 1.4826 * MAD of the finite values of `v` (time order kept for the autocorrelation).
// Why MAD: the baseline may contain a few outliers (sensor glitches, a transient); MAD has a 50 %
// breakdown point, so one glitch does not inflate the scale and blind the detector.
// Fallbacks when MAD == 0 (quantised or constant data): the standard deviation, then
// `relative_floor * |median|`, then `absolute_floor`, so the scale is always > 0.
RobustStats robust_stats(const std::vector<double>& v, double relative_floor = 1e-6, double absolute_floor = 1e-12);

// Upper-tail standard normal quantile: z such that P(Z > z) = p, for 0 < p < 1
// (Acklam's rational approximation refined by one Halley step; |error| < 1e-12).
double normal_upper_quantile(double p);

// Upper-tail chi-square quantile with `dof` degrees of freedom: x such that P(X > x) = p.
// Wilson-Hilferty cube-root approximation: relative error < 1 % for dof >= 10, < 2 % for dof >= 4 in the
// far tail; it overestimates tail quantiles at small dof, i.e. errs towards fewer false alarms.
double chi_square_upper_quantile(int dof, double p);

// Siegmund's approximation of the in-control average run length of a one-sided CUSUM
// S_n = max(0, S_{n-1} + z_n - k) on i.i.d. N(0,1) data with decision interval h:
//   ARL0 ~= (exp(2 k b) - 2 k b - 1) / (2 k^2),  b = h + 1.166     (Siegmund 1985, eq. 2.57)
double cusum_arl0(double k, double h);

// Inverse of cusum_arl0 in h (bisection; ARL0 is increasing in h): the decision interval that gives
// the target in-control ARL (in observations) for reference value k.
double cusum_threshold_for_arl0(double k, double target_arl0);

}  // namespace causal::alarms
