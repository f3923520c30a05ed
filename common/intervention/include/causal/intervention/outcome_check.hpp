// The twin checks its own prediction after an approved intervention (Eigen + std only).
//
// For an intervention do(z_j := z_j + delta) on the lever j over snapshots [s, s + D) and the alarmed target k
// (log levels z, as the condition-level model runs), everything is frozen from the data before the start, at
// snapshot s - 1 (so the same data give the same outcome, whenever the approval arrived):
//  * the twin's predicted effect on z_k, median and interval [lo, hi] of coverage c (the what-if the
//    recommender answers at s - 1: a steady state, or the effect H snapshots after the start);
//  * a forecast of z_k WITHOUT the intervention: an AR(1) around the mean of the last W snapshots before s,
//        f[t] = m + rho^(t - s + 1) (z_k[s - 1] - m),                                               (O1)
//    rho the lag-1 autocorrelation of those W values (clipped to [0, 0.99]).
// The comparison snapshots C: the last K of the window for a steady-state answer, {s + H} for a horizon answer.
// Once every snapshot of C is observed,
//     observed = mean_{t in C} (z_k[t] - f[t]),                                                     (O2)
// and the check interval is the predicted one widened by the forecast's own error (a forecast of noise is not
// exact): [lo - q sd_f, hi + q sd_f], q the normal quantile of (1 + c) / 2, with
//     sd_f^2 = s2 / K^2 sum_{t, u in C} rho^|t-u| (1 - rho^(2 min(h_t, h_u))) / (1 - rho^2) + s2 / W_eff,   (O3)
// s2 = (1 - rho^2) var(z_k) the AR(1) innovation variance, h_t = t - s + 1 the forecast step, W_eff = W (1 - rho) /
// (1 + rho) the effective size of the mean's sample. inside = observed in the check interval; improved =
// observed < 0 (the alarmed channel went down against its forecast). LeverTrust (lever_trust.hpp) learns from
// every checked outcome.
#pragma once

#include "causal/intervention/lever_trust.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace causal::intervention {

struct OutcomeParams {
  int pre_window = 24;     // W: snapshots before the start the forecast is fitted on
  int min_pre = 12;        // fewer (a gap, a young group): no forecast, status "no_forecast"
  int compare_last = 6;    // K for a steady-state answer (capped by the duration)
  std::size_t max_history = 4096;  // snapshots kept per group (older ones are dropped)
  LeverTrustParams trust;
};

struct InterventionPlan {
  std::string request_id, asset_group, recommendation_id;
  int lever = 0, target = 0;  // 0-based channels
  double delta = 0.0;         // log-level change of the lever
  std::uint64_t start = 0, duration = 0;
};

// The what-if answer frozen at s - 1 (log units of the target).
struct Prediction {
  bool ok = false;
  std::string why;                        // when !ok
  bool steady_state = false;              // else a horizon answer
  int horizon = 0;                        // H of a horizon answer
  double effect = 0.0, low = 0.0, high = 0.0, coverage = 0.9;
};

struct Outcome {
  InterventionPlan plan;
  std::string status;                     // "checked", "no_forecast", "no_data"
  std::string why;                        // for no_forecast / no_data
  std::uint64_t compare_from = 0, compare_to = 0;
  double predicted = 0.0, predicted_low = 0.0, predicted_high = 0.0, coverage = 0.0;  // log units, as predicted
  double check_low = 0.0, check_high = 0.0;  // widened by the forecast's error (O3)
  double forecast_sd = 0.0;
  double observed = 0.0;                  // (O2), log units; NaN unless checked
  bool inside = false, improved = false;
  double lever_trust = 0.0;               // after this outcome
  bool lever_claimed = true;
};

// 100 (e^d - 1): a log-level change in percent of the level.
double to_percent(double log_change);

class OutcomeCheck {
 public:
  explicit OutcomeCheck(OutcomeParams params = {});  // throws std::invalid_argument for bad params

  // An approved intervention (once per request id: a repeat returns false). It is frozen when snapshot
  // start - 1 (or later) of its group has been observed: see due().
  bool approve(const InterventionPlan& plan);
  // Plans of `group` that are due for their frozen prediction now that `index` is observed (start - 1 <= index),
  // in request-id order. The caller answers the what-if on the model as of `index` and calls freeze().
  std::vector<InterventionPlan> due(const std::string& group, std::uint64_t index) const;
  // Freezes the forecast (O1) from the history before the start, and the prediction. A plan that cannot be
  // checked (no prediction, too little history) is finished at once into `done`.
  void freeze(const std::string& request_id, const Prediction& prediction, std::vector<Outcome>& done);
  // One condition-level observation of a group (log levels, G values). Non-finite values are rejected and
  // counted. Finished outcomes go to `done`.
  void observe(const std::string& group, std::uint64_t index, const Eigen::VectorXd& log_levels,
               std::vector<Outcome>& done);

  const LeverTrust& trust() const { return trust_; }
  std::size_t pending() const { return pending_.size(); }
  std::uint64_t rejected_non_finite() const { return rejected_; }

 private:
  struct Forecast {
    double mean = 0.0, rho = 0.0, last_dev = 0.0, variance = 0.0;
    int window = 0;
  };
  struct Pending {
    InterventionPlan plan;
    bool frozen = false;
    Prediction prediction;
    Forecast forecast;
    std::uint64_t compare_from = 0, compare_to = 0;
  };
  std::optional<Forecast> fit_forecast(const std::string& group, int target, std::uint64_t start) const;
  double forecast_sd(const Pending& p) const;  // (O3)
  Outcome finish(const Pending& p, const std::string& status, const std::string& why);
  void check_ready(const std::string& group, std::uint64_t index, std::vector<Outcome>& done);

  OutcomeParams params_;
  LeverTrust trust_;
  std::map<std::string, std::map<std::uint64_t, Eigen::VectorXd>> history_;  // group -> index -> log levels
  std::map<std::string, Pending> pending_;  // by request id
  std::map<std::string, bool> seen_;        // request ids ever approved
  std::uint64_t rejected_ = 0;
};

}  // namespace causal::intervention
