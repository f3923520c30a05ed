// The two standard anchors the twin's time-to-level forecast is scored beside (causal-prognosis-eval), on the
// same data at the same decision points: the log level over the channel's healthy reference since the alarm's
// onset, y(t), t in hours.
//   (a) Log-linear Theil-Sen trend (Sen 1968) with bootstrap intervals: the median of the pairwise slopes and of
//       the residuals; the 90 % interval of the crossing time from a pairs bootstrap (Efron and Tibshirani 1993,
//       ch. 9) of the same fit; unknown when the fitted slope is not rising or the late end is "never".
//   (b) Random walk with drift, y(t) = y0 + mu t + sigma W(t): the first passage of a level gap g > 0 above the
//       last observation is inverse Gaussian with mean g / mu and shape g^2 / sigma^2 (Chhikara and Folks 1989,
//       ch. 2; the Wiener degradation model of Whitmore 1995); mu, sigma^2 by maximum likelihood from the
//       increments; unknown when mu <= 0.
#pragma once

#include "prognosis_scoring.hpp"

#include <cstdint>
#include <vector>

namespace causal::prognosis_eval {

// Theil-Sen fit and its bootstrap, made once per decision point and asked for several levels.
class TheilSenBootstrap {
 public:
  // t, y: since the onset; at most max_points evenly thinned (the last one kept); draws bootstrap fits; seed
  // fixes them (same input, same output).
  TheilSenBootstrap(const std::vector<double>& t, const std::vector<double>& y, int draws, std::uint64_t seed,
                    int max_points = 60);
  // Hours until the log level (over the reference) reaches log_ratio; coverage of the interval.
  Prediction time_to(double log_ratio, double coverage) const;

 private:
  bool fitted_ = false;
  double slope_ = 0, now_ = 0;            // point fit: slope, fitted level at the last point
  std::vector<double> slopes_, nows_;      // bootstrap fits
};

// Random walk with drift on the same data.
class DriftRandomWalk {
 public:
  DriftRandomWalk(const std::vector<double>& t, const std::vector<double>& y);
  Prediction time_to(double log_ratio, double coverage) const;

 private:
  bool fitted_ = false;
  double mu_ = 0, sigma2_ = 0, now_ = 0;
};

// P(T <= t) of the inverse Gaussian with mean m and shape lambda (exposed for the unit test).
double inverse_gaussian_cdf(double t, double m, double lambda);

}  // namespace causal::prognosis_eval
