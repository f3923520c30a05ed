// A third, model-light way to put an interval on the time to a level (causal-prognosis-eval's row
// "conformal"): split-conformal prediction (Vovk, Gammerman and Shafer 2005; the rolling form of Stankeviciute,
// Alaa and van der Schaar 2021 for time series) on the channel's own level forecasts since the alarm's onset.
// Data: hourly medians m_k of the log level over the healthy reference since the onset (the blocks remove the
// snapshot noise). From every past origin k the same point forecast of the level h hours ahead is made,
// m_k + v_k h, with v_k the mean log rate since the onset (the long-run rate, which an episode moves least); its
// errors r_k(h) = m_{k+h} - (m_k + v_k h) at each whole horizon h are the channel's own record of how wrong such a
// forecast has been that far ahead. Now: the level band at horizon h is m + v h + [q_low(h), q_high(h)], the
// empirical quantiles of r(h); the interval of the time to log level L runs from the first h whose upper band
// reaches L to the first h whose lower band does; the point from the median error. Unknown where the horizon
// needed has fewer than min_errors past errors (the channel has not been watched that long), where the mean rate
// is not rising, or where the lower band never reaches L within the errors on record. Nothing is fitted: the
// block (1 h) and the least number of errors per horizon (8) are fixed a priori. Horizons count hourly blocks
// that hold data (a recording gap has none); the rates use the blocks' median times.
#pragma once

#include "prognosis_scoring.hpp"

#include <vector>

namespace causal::prognosis_eval {

class ConformalLevel {
 public:
  // t: hours since the onset (increasing), y: log level over the reference, as the anchors take them.
  ConformalLevel(const std::vector<double>& t, const std::vector<double>& y, int min_errors = 8);
  Prediction time_to(double log_ratio, double coverage) const;

 private:
  std::vector<double> median_;       // hourly medians, oldest first
  std::vector<double> time_;         // their blocks' median times
  std::vector<double> rate_;         // mean log rate since the onset at each origin
  double offset_ = 0;                // hours from the last block's median time to now
  int min_errors_;
};

}  // namespace causal::prognosis_eval
