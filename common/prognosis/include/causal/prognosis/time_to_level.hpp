// Time until a channel's level reaches a threshold, from the posterior of its degradation trend.
//
// Closed form (no Monte Carlo, so the service's output is a deterministic function of its checkpointed
// state). With the trend posterior x = [m, b, a] ~ N(x, P) at now, the log level s hours ahead is Gaussian:
//   m(s) ~ N(mu(s), sigma^2(s)),  h(s) = [1, s, s^2/2],  d^2(s) = f q s^5 / 20,
//   mu(s) = h(s) x + sqrt(2/pi) d(s),  sigma^2(s) = h(s) P h(s)^T + (1 - 2/pi) d^2(s) + f q_level s
// (f = TrendParams::forecast_diffusion: how much of the filter's acceleration diffusion the forecast keeps;
// with the online calibration, q and h P h^T are multiplied by TrendState::inflation >= 1).
// d(s) is the future acceleration's random walk folded to non-negative increments, because wear does not
// heal: its contribution to the level is approximated by the mean and variance of a half-normal of scale d
// (a symmetric diffusion made the late side of the interval run past any horizon, and on the simulations
// the truth came EARLIER than predicted in 9 of 10 misses: docs/prognosis.md).
// The first-passage time T to the log threshold L is approximated from these marginals (the residual-life
// distribution of Gebraeel, Lawley, Li and Ryan 2005, "Residual-life distributions from component
// degradation signals: a Bayesian approach", IIE Transactions 37(6):543-557):
//   P(T <= t) ~= max_{s <= t} Phi((mu(s) - L) / sigma(s)).
// For paths that rise monotonically after now (f = 0, b >= 0, a >= 0 in every draw that matters) this is
// exact: such a path below L now is above L at time t iff it crossed before t. Otherwise the marginal ignores
// paths that crossed and fell back (a lower bound); the running max keeps the distribution monotone. For a
// straight line (a = 0, P_a = 0, f = 0) the median is (L - m) / b. The lower end of the interval may be moved
// earlier by a pessimistic scenario (PrognosisParams::pessimistic_z), never the median or the upper end. Quantiles p of T: the first t with
// (mu(t) - L) / sigma(t) >= Phi^-1(p), found on a log-spaced grid and refined by bisection.
#pragma once

#include "causal/prognosis/degradation_trend.hpp"

#include <cstdint>
#include <string>

namespace causal::prognosis {

// The levels a prognosis is given for (Prognosis.level in the IDL).
enum class Level { warning = 0, critical = 1, end_of_life = 2 };
const char* to_string(Level level);  // "warning", "critical", "end_of_life"

// The excess-growth model (excess_growth.hpp): hourly medians of the log excess since the onset. Fixed before
// any evaluation (one hour: the alarm engine's snapshots are 10 min apart, six per median; four hours: the
// least for a drift and a diffusion from three increments; three healthy sds: ln w of a median excess below it is
// mostly noise); not fitted on any run.
struct ExcessGrowthParams {
  double block_hours = 1.0;     // the medians' block length
  int min_blocks = 4;           // blocks with a usable excess needed before an answer
  double min_excess_sd = 3.0;   // a block is usable when its median excess is >= this x the healthy sd
  bool power_law = true;        // also the power-law shape (ln w linear in ln tau), likelihood-weighted
  void validate() const;        // throws std::invalid_argument naming the bad field
};

struct PrognosisParams {
  TrendParams trend;
  ExcessGrowthParams excess;
  // Which model answers (ChannelTrends::time_to): the local trend while its own recent level forecasts fit
  // (TrendState::inflation, the running mean square of its standardised errors over calibration_memory checks,
  // at most trend_fit_limit), else the excess-growth model; each answers where the other cannot. 2.51: the 99 %
  // point of chi^2 with 8 degrees of freedom over 8 (the inflation's memory), a goodness-of-fit test of the
  // local trend at 1 %; not fitted on any run. 0: the excess-growth model first; infinity: the local trend only.
  double trend_fit_limit = 2.51;
  bool long_run_fills_unknown = true;  // the long-run model also answers where a fitting local trend says unknown
  // Observations per channel kept for the excess-growth model and in the checkpoint (2016: 14 days of
  // 10-minute snapshots, 32 kB per channel; a wear history from the onset longer than that is cut to its end).
  std::uint64_t history_limit = 2016;
  // End of life as a multiple of the baseline level. 6x = +15.6 dB: one and a half 6-dB steps beyond the
  // critical level (4x, +12 dB) of the alert ladder the alarm engine uses (2x warning, 4x critical). A bearing
  // at 6x its healthy vibration has spalled far beyond an early fault; the IMS run-to-failure tests were
  // stopped there (test 2, bearing 1: 5.8x its baseline meanabs at the last running snapshot), so this is also
  // where a test rig's operator judged "failed". Configurable (alarms.yaml prognosis.end_of_life_ratio).
  double end_of_life_ratio = 6.0;
  double coverage = 0.9;          // of [hours_low, hours_high]
  // "unknown" instead of a meaningless interval:
  double min_trend_z = 1.645;     // the slope must be significantly positive (one-sided 95 %): b / sd(b)
  int min_points_since_onset = 6; // observations since the alarm's onset (1 h at 10-min spacing)
  double max_horizon_hours = 2000.0;  // a quantile beyond this is "not within the horizon" (about 12 weeks)
  double max_width_factor = 10.0; // hours_high > this x hours: the interval spans more than a factor of 10
  // Lower end of the interval: the earlier of the Gaussian forecast's low quantile and the time at which a
  // pessimistic scenario reaches the level (slope and acceleration at their upper pessimistic_z quantile, the
  // slope growing exponentially, the level at its upper quantile too; sds scaled by the calibration's
  // inflation; time_to_level.cpp). 0 = off (the Gaussian quantile only). 4: chosen on simulation seeds 1-20
  // (2.5 left 27 % of the known intervals with the truth before them), judged on seeds 101-120 and IMS.
  double pessimistic_z = 4.0;
  void validate() const;          // throws std::invalid_argument naming the bad field
};

struct TimeToLevel {
  bool known = false;             // hours, hours_low, hours_high are finite and meaningful
  bool reached = false;           // the filtered level is at or above the threshold (hours = 0)
  double hours = 0.0;             // median; NaN when unknown
  double hours_low = 0.0, hours_high = 0.0;  // interval; NaN when unknown
  std::string why;                // when unknown: why, in words
};

// P(T <= hours) as above (max over a grid of s <= hours); exposed for tests.
double crossing_probability(const TrendState& s, const TrendParams& trend, double log_threshold, double hours);

// Time from the trend's last observation until the log level reaches log_threshold.
TimeToLevel time_to_level(const TrendState& s, const TrendParams& trend, double log_threshold,
                          std::uint64_t points_since_onset, const PrognosisParams& params);

}  // namespace causal::prognosis
