// Time to a level from the growth of a channel's log excess over its healthy reference since the alarm's onset:
// Gebraeel's exponential degradation model (Gebraeel, Lawley, Li and Ryan 2005, "Residual-life distributions
// from component degradation signals: a Bayesian approach", IIE Transactions 37(6)) applied to the log excess
// w(t) = log(level / reference) with a Brownian error (the Wiener form of Gebraeel 2008 / Elwany and Gebraeel
// 2009):
//   ln w(t) = phi + mu t + sigma B(t).
// Why the log excess: accelerating wear (a spall that grows at a rate proportional to its size) makes the log
// level rise ever faster, w = c (exp(lambda t) - 1) (the simulated run-to-failure channels,
// tools/causal_prognosis_eval/run_to_failure_sim.hpp), so ln w is a straight line in time once w is well above the
// noise, and a Brownian error around it carries the episodes (rises and holds) of real wear as diffusion, not as
// a change of rate. A local trend (degradation_trend.hpp) follows each episode; this model follows the whole
// history since the onset.
//
// Data: hourly medians of w (a spike is one snapshot of six; the median is also the alarm's statistic), kept
// where the median excess is at least min_excess_sd healthy measurement sds (below that ln w is noise).
// Two shapes, each a Wiener process of ln w on its own clock v: v = t (exponential excess, w = c exp(mu t)) and
// v = ln tau, tau the hours since the onset (power-law excess, w = a tau^k: the early, nearly linear growth of
// w = c (exp(lambda tau) - 1)). Estimates per shape (Whitmore 1995, a Wiener process observed at irregular times):
//   mu = (z_n - z_1) / (v_n - v_1),  sigma^2 = sum (dz_k - mu dv_k)^2 / (dv_k - B_k / 3) / (n - 1)
// (B_k / 3: the blocks' own averaging of the path), mu ~ N(mu_hat, sigma^2 / (v_n - v_1)). The shapes are weighted
// by their maximised likelihoods (Bayesian model averaging with equal priors; both have two parameters). The
// first passage of ln w from z_n to D = ln(log_ratio) on a shape's clock is inverse Gaussian for a known drift,
//   P(V <= v | mu) = Phi((mu v - g) / (sigma sqrt v)) + exp(2 mu g / sigma^2) Phi((-mu v - g) / (sigma sqrt v)),
// g = D - z_n > 0 (Chhikara and Folks 1989, eq. 2.1; defective for mu < 0); the drift's uncertainty is integrated
// out on a grid (deterministic: no Monte Carlo). "Unknown" unless the likelier shape's drift is significantly
// positive (the local trend's min_trend_z test) and the interval spans at most max_width_factor.
#pragma once

#include "causal/prognosis/time_to_level.hpp"

#include <string>
#include <vector>

namespace causal::prognosis {

// t: hours (increasing), w: log excess over the reference at those times (NaN skipped), since the onset;
// noise_std: the channel's healthy measurement sd of the log level; log_ratio = ln(level / reference) > 0.
// Returns "reached" when the last block's median is at the level (the caller decides with the alarm's event),
// else the median and the coverage interval of the time from t.back(), or unknown with the reason.
// too_little_data (optional): set when unknown only because too few hours stand above the noise yet.
TimeToLevel excess_growth_time_to(const std::vector<double>& t, const std::vector<double>& w, double noise_std,
                                  double log_ratio, const PrognosisParams& params, bool* too_little_data = nullptr);

// P(T <= t) of the first passage above, for a drift mu with sd mu_sd (exposed for tests).
double excess_passage_probability(double gap, double mu, double mu_sd, double sigma2, double t);

}  // namespace causal::prognosis
