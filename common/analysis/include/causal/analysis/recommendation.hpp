// Recommendations for an alarmed target channel: candidate interventions "shift channel j by delta"
// (sustained, delta < 0 = reduce) answered by the bounded-answer rule (bounded_answer.hpp: steady state,
// effect after H snapshots, or refused), and said in plain language:
//   "Reduce vibration at bearing 3 by 0.02 g: bearing 1 is predicted to drop by 0.015 g (90% interval
//    0.010..0.019) at steady state, 0.008 at once."
// Ranking accounts for uncertainty: by the interval bound in the helpful direction (the upper bound of
// the target's change: the reduction we are 95 % sure of at 90 % coverage), so a large but uncertain
// effect does not beat a smaller sure one. An action whose interval includes no change is not `reliable`
// and is ranked after every reliable one; the service says "no reliable lever" when none is.
// The prediction is only as causal as the structural model (see structural_model.hpp LIMITS).
#pragma once

#include "causal/analysis/bounded_answer.hpp"
#include "causal/analysis/uncertainty.hpp"

#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace causal::analysis {

struct CandidateIntervention {
  int channel = 0;     // 0-based j (must differ from the target)
  double delta = 0.0;  // sustained shift of y_j; negative = reduce
};

struct Recommendation {
  CandidateIntervention action;
  AnalysisStatus status = AnalysisStatus::ok;  // of the model at the posterior mean
  std::string message;            // why this kind of answer (answer.reason)
  BoundedAnswer answer;           // every channel, with the stability diagnostics
  double immediate = 0.0;         // median change of the target at once (W2)
  double effect = 0.0;            // median of the answered change of the target (steady state or after H);
                                  // < 0 is a reduction; NaN when refused
  double steady_state = 0.0;      // = effect for a steady-state answer, NaN otherwise (no steady state)
  double lower = 0.0;             // interval of `effect` (same draws: lower <= effect <= upper)
  double upper = 0.0;
  bool interval_valid = false;    // answered (not refused)
  bool reliable = false;          // answered and upper < 0: a reduction even at the interval's helpful-side bound
  double coverage = 0.0;
  std::string text;               // the plain-language sentence
};

struct RecommendationOptions {
  UncertaintyOptions uncertainty;
  std::vector<std::string> channel_names;  // G names; "channel <j+1>" when empty
  std::string unit;                        // appended to amounts, e.g. "g"; may be empty
  AnswerRule rule;                         // when steady state, when horizon, when refused
  DrawSharing draw_sharing = DrawSharing::shared;  // bounded_answer.hpp: the same answers either way
};

// Sorted: reliable first, then answered but unreliable, then refused; within each by `upper` ascending (the
// largest reduction we are sure of first), ties by channel. Throws std::invalid_argument for a bad target/candidate channel, a candidate on the target
// itself, a non-finite delta, or names of the wrong count.
std::vector<Recommendation> rank_interventions(const estimation::SvarLayout& layout, const FactorPosterior& posterior, int target,
                                               const std::vector<CandidateIntervention>& candidates,
                                               const RecommendationOptions& options = {});

// One candidate per channel j != target with current_j > baseline_j: delta_j = -fraction * (current_j -
// baseline_j) (bring a fraction of the excess back to baseline). Throws std::invalid_argument for size
// mismatches or fraction outside (0, 1].
std::vector<CandidateIntervention> candidates_from_excess(const Eigen::VectorXd& current, const Eigen::VectorXd& baseline,
                                                          int target, double fraction = 1.0);

// The sentence for one recommendation (what rank_interventions puts in .text).
std::string describe_recommendation(const Recommendation& rec, int target, const std::vector<std::string>& names,
                                    const std::string& unit);

// Fixed-point text with two significant digits of `reference` (e.g. 0.015 -> 3 decimals).
int decimals_for(double reference);

}  // namespace causal::analysis
