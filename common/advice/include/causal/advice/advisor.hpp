// Prescriptive side of alarm-recommender: keeps each asset group's latest condition-level causal model
// (factors and their standard deviations) and turns it into ranked interventions when an alarm is raised,
// and into what-if answers on request (common/analysis does the causal arithmetic).
//
// Units: the condition-level model runs on log(feature) when the estimator's log_transform is on, so an
// intervention delta is a change of log level: -0.1 means "reduce that bearing's RMS by 1 - e^-0.1 = 9.5 %".
// The texts translate to percent of the channel's current level (effect_units.hpp: 100 (e^d - 1), never
// below -100 %). Every answer follows the bounded-answer rule (bounded_answer.hpp): a steady state only
// when the model settles with margin, else the effect after H snapshots, else a refusal with the reason;
// point = median and interval = quantiles of the same posterior draws. Uncertainty: the filter's factor covariance is block-diagonal by outcome
// and each outcome block of a CausalFactorBatch carries its outcome's full block P_k, so intervals use the full posterior
// N(x, blockdiag(P_k)) including within-outcome correlations. When any block is missing (an older
// estimator, a malformed block) they fall back to diagonal blocks from the standard deviations, which
// ignores those correlations (approximate intervals).
#pragma once

#include "causal/alarms/observation.hpp"
#include "causal/analysis/bounded_answer.hpp"
#include "causal/analysis/effect_units.hpp"
#include "causal/analysis/recommendation.hpp"
#include "causal/analysis/uncertainty.hpp"
#include "causal/estimation/svar_layout.hpp"

#include <Eigen/Core>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace causal::advice {

// One condition-level filter observation of an asset group's model, as the advisor needs it (plain data: the
// service fills it from the estimator's CausalFactorBatch stream, a tool or test from its own run).
struct ModelObservation {
  std::string asset_group;
  std::vector<std::string> channel_names;  // G, outcome order
  std::vector<std::string> factor_names;   // F, outcome-major
  int lag_order = 1;
  alarms::Observation observation;
  // Per outcome k (0-based), the full factor covariance P_k. Empty unless EVERY outcome carried a valid block
  // (factors.size() square), so a consumer either has all of them or none.
  std::vector<Eigen::MatrixXd> covariance_blocks;
};

struct AdvisorParams {
  bool enabled = true;
  int max_per_alarm = 3;          // recommendations published per raised alarm
  double excess_fraction = 1.0;   // candidate j: bring this fraction of j's excess over baseline back
  double min_excess_percent = 0.0; // ... if j is at least this many percent above its baseline (less is normal spread)
  double coverage = 0.9;          // interval coverage
  int draws = 2000;               // Monte Carlo draws
  // Candidate levers evaluated per alarm: those with the largest excess over their baseline. Each costs `draws`
  // solves of the G-channel model (the draws themselves are shared); all 19 of a 20-channel group took ~10 s per
  // alarm on a loaded 2-core machine and the recommender fell behind the estimator. 4 keeps every candidate of a
  // 4- or 5-channel group (20 channels: ~0.5 s CPU per alarm, docs/advice.md "Cost of the advice at width").
  int max_candidates = 4;
  // Candidates share one set of posterior draws (analysis::DrawSharing; the same answers either way). Not a
  // configuration key: per_query is the former way, for the equivalence test and tests/bench/bench_advice_cost.cpp.
  analysis::DrawSharing draw_sharing = analysis::DrawSharing::shared;
  bool model_log_features = true; // the estimator's condition_level.log_transform
  analysis::AnswerRule rule;      // steady state / horizon / refusal (alarms.yaml recommendations.answer_*)
  // The healthy reference model (Advisor::set_health): a model captured past learning with no degradation alarm
  // open becomes the reference once this many further observations passed so (144 = 1 day at 10 min).
  int reference_confirm_observations = 144;
};

// Stability and units of one answer, as published (Recommendation, WhatIfReply).
struct AnswerDiagnostics {
  std::string kind = "refused";   // analysis::to_string(AnswerKind): steady_state, horizon, refused
  int horizon_snapshots = 0;      // H of a horizon answer
  double spectral_radius = 0.0;   // of the intervened model at the estimate
  int draws = 0, unstable_draws = 0;
  double unstable_share = 0.0;
};

struct AdviceItem {
  int rank = 0;                   // 1 = best
  int target = 0;                 // 0-based alarmed channel
  int intervene = 0;              // 0-based channel to act on
  double delta = 0.0;             // model units (log level when model_log_features)
  std::string reduction;          // the size of -delta in words, e.g. "9.5 %" (log model) or "0.02" (raw)
  double immediate = 0.0;         // median change of the target at once (model units)
  double steady_state = 0.0;      // median steady-state change; NaN unless diag.kind == steady_state
  double effect = 0.0;            // median of the answered change (steady state or after H); NaN when refused
  double lower = 0.0, upper = 0.0, coverage = 0.0;  // interval of `effect`
  double percent = 0.0, percent_lower = 0.0, percent_upper = 0.0;  // the same in % of the target's current level
  double level_change = 0.0;      // median in the feature's own units
  bool reliable = false;          // the interval excludes "no reduction"
  AnswerDiagnostics diag;
  std::string summary;            // the one line: horizon, interval, confidence, stability
  std::string text;
  std::string action;             // set by the advice policy: what to do (the published Recommendation.action)
  // The same intervention answered on the healthy reference model (the causal links before the fault).
  // "held": there too (reliable, or at least half the effect with the same sign); "appeared": not (a link that
  // came with the fault: a common cause of both rises explains it as well, so no lever may be claimed on it);
  // "none": no confirmed reference yet (Advisor::set_health).
  std::string reference = "none";
  double reference_percent = 0.0; // the reference model's median effect, % of the target's current level
};

struct WhatIfAnswer {
  bool ok = false;
  std::string error;
  // G each, model units; medians and interval of the same draws. steady_state: NaN unless a steady-state answer.
  Eigen::VectorXd immediate, steady_state, effect, lower, upper;
  Eigen::VectorXd percent, percent_lower, percent_upper;  // of each channel's current level
  AnswerDiagnostics diag;
  std::string summary;
  std::string text;
  std::vector<std::string> channel_names;  // G, the order of the effects (empty when the group is unknown)
};

class Advisor {
 public:
  explicit Advisor(AdvisorParams params) : params_(params) {}

  // A condition-level filter observation updates the asset group's model (the caller passes no other kind).
  void update(const ModelObservation& a);
  // The group's alarm state now: still learning its baseline, and whether a degradation alarm is open. While
  // it is neither, the advisor captures the current model as a candidate reference; a candidate becomes the
  // group's healthy reference after reference_confirm_observations more observations in that state (a fault
  // that began after the capture cannot have shaped it). No reference before the first confirmation.
  void set_health(const std::string& asset_group, bool learning, bool degraded);
  bool has_model(const std::string& asset_group) const { return models_.count(asset_group) > 0; }
  // True when the group's latest model has full per-outcome covariance blocks (else: diagonal fallback).
  bool full_covariance(const std::string& asset_group) const;

  // Interventions that most reduce `target`, from the channels above their baseline. `baseline_features`:
  // per-channel baseline of the raw feature (e.g. RMS). Empty result: `why` says why.
  std::vector<AdviceItem> advise(const std::string& asset_group, int target, const Eigen::VectorXd& baseline_features,
                                 std::string& why) const;
  // Every candidate, ranked (reliable ones first), without the max_per_alarm cut: the advice policy
  // (advice_policy.hpp) decides which may be claimed as levers.
  std::vector<AdviceItem> evaluate(const std::string& asset_group, int target, const Eigen::VectorXd& baseline_features,
                                   std::string& why) const;
  // The group's snapshot spacing in hours (median of the recent spacings of condition-level observations);
  // NaN before two observations.
  double snapshot_hours(const std::string& asset_group) const;

  // do(y_j := y_j + delta) in model units; sustained or a one-snapshot impulse.
  WhatIfAnswer what_if(const std::string& asset_group, int channel, double delta, bool sustained) const;

 private:
  struct FactorSnapshot {
    Eigen::VectorXd factors, factor_std;
    std::vector<Eigen::MatrixXd> blocks;
    std::uint64_t at = 0;  // the model's observation count when captured
  };
  struct AssetModel {
    std::unique_ptr<estimation::SvarLayout> layout;
    std::vector<std::string> channel_names;
    Eigen::VectorXd factors, factor_std, features;
    std::vector<Eigen::MatrixXd> blocks;  // P_k per outcome; empty when the latest observation had none
    std::int64_t last_time_ns = 0;
    std::vector<double> spacings_h;       // the last few snapshot spacings (hours), for horizons in hours
    std::uint64_t observations = 0;
    bool settled = false;                 // past learning and no degradation alarm open (set_health)
    std::optional<FactorSnapshot> reference, candidate;
  };
  static FactorSnapshot snapshot_of(const AssetModel& m);
  static void note_reference(AssetModel& m, int confirm);
  analysis::FactorPosterior posterior(const estimation::SvarLayout& layout, const FactorSnapshot& s) const;
  void compare_with_reference(const AssetModel& m, int target, const std::vector<analysis::CandidateIntervention>& candidates,
                              const analysis::RecommendationOptions& options, double level,
                              std::vector<AdviceItem>& items) const;
  // Full blocks when usable, else diagonal blocks from factor_std.
  analysis::FactorPosterior posterior(const AssetModel& m) const;
  static bool blocks_usable(const AssetModel& m);
  Eigen::VectorXd to_model_units(const Eigen::VectorXd& features) const;
  std::string percent(double model_delta) const;    // signed change, e.g. "-9.5 %"
  std::string reduction(double model_delta) const;  // size of a reduction, e.g. "9.5 %" for delta < 0
  analysis::EffectUnits units(const AssetModel* m = nullptr) const;
  analysis::UncertaintyOptions uncertainty() const;

  AdvisorParams params_;
  std::map<std::string, AssetModel> models_;
};

// Rebuilds the estimator's layout from what a CausalFactorBatch stream carries (G, M, factor names); nullopt
// when no standard layout has exactly these names (then no advice is given).
std::optional<estimation::SvarLayout> layout_from_names(int channels, int lag_order, const std::vector<std::string>& names);

}  // namespace causal::advice
