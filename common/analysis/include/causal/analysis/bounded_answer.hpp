// What-if answers that exist: a steady state only when the model settles, else a bounded-horizon effect,
// else an explicit refusal. Point and interval come from the SAME posterior draws.
//
// Why: condition-level models on trending log levels sit near or past a unit root (self-lag 0.9999, 1.12).
// The steady state (I - A0c - sum A_lc)^{-1} e_j delta (intervention.hpp, W3) then either does not exist or
// amplifies the estimation error without bound (1 / (1 - rho)), and a point computed at the posterior mean
// can lie outside an interval formed from the draws that happened to settle.
//
// The rule (documented in README "Prescriptive analytics"), with rho the companion spectral radius at the
// posterior mean, the larger of the model as estimated and the system that runs after the intervention
// (intervened for a sustained shift), and "unstable share" the share of ALL posterior draws where either
// has rho >= 1. Why the model itself too: a model that does not settle describes trending data, and a
// steady state of its intervened system extrapolates to a regime the data never showed (on simulated
// explosive systems such answers came out confidently wrong-signed):
//   steady_state  rho <= max_stable_radius AND unstable share <= max_unstable_share: the long-run effect
//                 (sustained: W3; impulse: cumulative W4) from the draws that settle; the unstable ones
//                 are counted and reported with the answer.
//   refused       rho >= 1 (past a unit root at the estimate) AND unstable share > refuse_unstable_share,
//                 or (I - A0c) singular at the estimate or in more than refuse_unstable_share of the draws:
//                 no effect is predicted, the reason says why.
//   horizon       otherwise: the effect H = horizon_snapshots snapshots after the change started
//                 (sustained: d[n0 + H]; impulse: sum of d[n0 .. n0 + H]), computed by iterating (W1)
//                 (no inverse), from every identifiable draw, stable or not.
// The answered effect and the immediate effect (W2) are summarised by the median (point) and the
// (1-c)/2, (1+c)/2 quantiles of the same draws: the point always lies inside its interval.
#pragma once

#include "causal/analysis/analysis_status.hpp"
#include "causal/analysis/intervention.hpp"
#include "causal/analysis/structural_model.hpp"
#include "causal/analysis/uncertainty.hpp"

#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace causal::analysis {

enum class AnswerKind { steady_state, horizon, refused };

struct AnswerRule {
  double max_stable_radius = 0.98;     // steady state only with this margin below a unit root
  double max_unstable_share = 0.05;    // ... and at most this share of unstable posterior draws
  int horizon_snapshots = 12;          // H of a horizon answer (>= 1)
  double refuse_unstable_share = 0.9;  // past a unit root with more unstable draws than this: refuse
};
// Throws std::invalid_argument for radius outside (0, 1), shares outside [0, 1], H < 1.
void validate_rule(const AnswerRule& rule);

// Median and central interval per channel (G each).
struct EffectSummary {
  Eigen::VectorXd median, lower, upper;
};

struct BoundedAnswer {
  AnswerKind kind = AnswerKind::refused;
  AnalysisStatus status = AnalysisStatus::ok;  // of the model at the posterior mean
  std::string reason;                          // why this kind was given (always filled)
  int horizon_snapshots = 0;                   // H of a horizon answer, 0 otherwise
  double spectral_radius = 0.0;                // at the posterior mean, see above (NaN when not identifiable)
  int draws = 0;                               // posterior draws taken
  int unstable_draws = 0;                      // draws whose model or intervened system has rho >= 1
  int singular_draws = 0;                      // draws with singular (I - A0c) or non-finite effects
  int draws_summarised = 0;                    // draws behind the quantiles
  double coverage = 0.0;
  EffectSummary immediate;  // change at once (W2), from the same draws as `effect`
  EffectSummary effect;     // the answered quantity (steady state / cumulative, or after H); NaN when refused
  double unstable_share() const { return draws > 0 ? static_cast<double>(unstable_draws) / draws : 0.0; }
  bool answered() const { return kind != AnswerKind::refused; }
};

// Throws std::invalid_argument for a bad rule, bad options (coverage, draws < 2), a bad channel or a
// posterior that does not match the layout. options.method is ignored: answers are always Monte Carlo.
BoundedAnswer answer_intervention(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                  const InterventionQuery& query, const AnswerRule& rule,
                                  const UncertaintyOptions& options);

// How several queries on one posterior are drawn. shared: one set of draws for all (common random numbers;
// each draw is sampled, assembled and checked for settling once, and a sustained query skips its intervened
// system's dynamics where the model itself does not settle, as that draw is unstable either way). per_query:
// each query draws and checks on its own (the way before sharing, kept as the reference the equivalence test
// and tests/bench/bench_advice_cost.cpp compare with). Both give every query the same answer, bit for bit, as
// answer_intervention on it alone: the draws come from the same seed.
enum class DrawSharing { shared, per_query };

// answer_intervention for each query, in order. Throws as answer_intervention.
std::vector<BoundedAnswer> answer_interventions(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                               const std::vector<InterventionQuery>& queries, const AnswerRule& rule,
                                               const UncertaintyOptions& options,
                                               DrawSharing sharing = DrawSharing::shared);

const char* to_string(AnswerKind kind);

}  // namespace causal::analysis
