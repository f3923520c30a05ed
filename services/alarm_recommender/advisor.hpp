// Prescriptive side of alarm-recommender: keeps each asset group's latest condition-level causal model
// (factors and their standard deviations) and turns it into ranked interventions when an alarm is raised,
// and into what-if answers on request (common/analysis does the causal arithmetic).
//
// Units: the condition-level model runs on log(feature) when the estimator's log_transform is on, so an
// intervention delta is a change of log level: -0.1 means "reduce that bearing's RMS by 1 - e^-0.1 = 9.5 %".
// The texts translate to percent. Uncertainty: the filter's factor covariance is block-diagonal by outcome
// and each CausalFactors message carries its outcome's full block P_k, so intervals use the full posterior
// N(x, blockdiag(P_k)) including within-outcome correlations. When any block is missing (an older
// estimator, a malformed block) they fall back to diagonal blocks from the standard deviations, which
// ignores those correlations (approximate intervals).
#pragma once

#include "observation_assembler.hpp"

#include "causal/analysis/recommendation.hpp"
#include "causal/analysis/uncertainty.hpp"
#include "causal/svar_layout.hpp"

#include <Eigen/Core>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace causal::recommender {

struct AdvisorParams {
  bool enabled = true;
  int max_per_alarm = 3;          // recommendations published per raised alarm
  double excess_fraction = 1.0;   // candidate j: bring this fraction of j's excess over baseline back
  double min_excess_percent = 0.0; // ... if j is at least this many percent above its baseline (less is normal spread)
  double coverage = 0.9;          // interval coverage
  int draws = 2000;               // Monte Carlo draws
  bool model_log_features = true; // the estimator's condition_level.log_transform
};

struct AdviceItem {
  int rank = 0;                   // 1 = best
  int target = 0;                 // 0-based alarmed channel
  int intervene = 0;              // 0-based channel to act on
  double delta = 0.0;             // model units (log level when model_log_features)
  double immediate = 0.0, steady_state = 0.0, lower = 0.0, upper = 0.0, coverage = 0.0;
  std::string text;
};

struct WhatIfAnswer {
  bool ok = false;
  std::string error;
  Eigen::VectorXd immediate, steady_state, lower, upper;  // G each, model units
  std::string text;
};

class Advisor {
 public:
  explicit Advisor(AdvisorParams params) : params_(params) {}

  // Condition-level filter observations update the asset group's model; others are ignored.
  void update(const AssembledObservation& a);
  bool has_model(const std::string& asset_group) const { return models_.count(asset_group) > 0; }
  // True when the group's latest model has full per-outcome covariance blocks (else: diagonal fallback).
  bool full_covariance(const std::string& asset_group) const;

  // Interventions that most reduce `target`, from the channels above their baseline. `baseline_features`:
  // per-channel baseline of the raw feature (e.g. RMS). Empty result: `why` says why.
  std::vector<AdviceItem> advise(const std::string& asset_group, int target, const Eigen::VectorXd& baseline_features,
                                 std::string& why) const;

  // do(y_j := y_j + delta) in model units; sustained or a one-snapshot impulse.
  WhatIfAnswer what_if(const std::string& asset_group, int channel, double delta, bool sustained) const;

 private:
  struct AssetModel {
    std::unique_ptr<SvarLayout> layout;
    std::vector<std::string> channel_names;
    Eigen::VectorXd factors, factor_std, features;
    std::vector<Eigen::MatrixXd> blocks;  // P_k per outcome; empty when the latest observation had none
  };
  // Full blocks when usable, else diagonal blocks from factor_std.
  analysis::FactorPosterior posterior(const AssetModel& m) const;
  static bool blocks_usable(const AssetModel& m);
  Eigen::VectorXd to_model_units(const Eigen::VectorXd& features) const;
  std::string percent(double model_delta) const;    // signed change, e.g. "-9.5 %"
  std::string reduction(double model_delta) const;  // size of a reduction, e.g. "9.5 %" for delta < 0

  AdvisorParams params_;
  std::map<std::string, AssetModel> models_;
};

// Rebuilds the estimator's layout from what a CausalFactors stream carries (G, M, factor names); nullopt
// when no standard layout has exactly these names (then no advice is given).
std::optional<SvarLayout> layout_from_names(int channels, int lag_order, const std::vector<std::string>& names);

}  // namespace causal::recommender
