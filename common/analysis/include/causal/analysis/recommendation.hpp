// Recommendations for an alarmed target channel: rank candidate interventions "shift channel j by
// delta" (sustained, delta < 0 = reduce) by the predicted steady-state change of the target (W3), most
// negative first, with its interval, and say it in plain language:
//   "Reduce vibration at bearing 3 by 0.02 g: bearing 1 is predicted to drop by 0.015 g (90% interval
//    0.010..0.019) at steady state, 0.008 at once."
// The prediction is only as causal as the structural model (see structural_model.hpp LIMITS).
#pragma once

#include "causal/analysis/uncertainty.hpp"

#include <causal/svar_layout.hpp>

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
  AnalysisStatus status = AnalysisStatus::ok;
  std::string message;            // why there is no prediction, when status != ok
  double immediate = 0.0;         // change of the target at once (W2)
  double steady_state = 0.0;      // change of the target at steady state (W3); < 0 is a reduction
  double lower = 0.0;             // interval of the steady-state change (same sign convention)
  double upper = 0.0;
  bool interval_valid = false;
  double coverage = 0.0;
  int draws_rejected = 0;         // Monte Carlo draws whose intervened system did not settle
  std::string text;               // the plain-language sentence
};

struct RecommendationOptions {
  UncertaintyOptions uncertainty;
  std::vector<std::string> channel_names;  // G names; "channel <j+1>" when empty
  std::string unit;                        // appended to amounts, e.g. "g"; may be empty
};

// Sorted: status ok first, then by steady_state ascending (largest predicted reduction first), ties by
// channel. Throws std::invalid_argument for a bad target/candidate channel, a candidate on the target
// itself, a non-finite delta, or names of the wrong count.
std::vector<Recommendation> rank_interventions(const SvarLayout& layout, const FactorPosterior& posterior, int target,
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
