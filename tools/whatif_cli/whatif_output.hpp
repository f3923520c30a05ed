// causal-whatif: text and CSV output.
#pragma once

#include "whatif_model.hpp"

#include <causal/analysis/bounded_answer.hpp>
#include <causal/analysis/counterfactual.hpp>
#include <causal/analysis/recommendation.hpp>
#include <causal/analysis/uncertainty.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace causal::whatif {

void print_model_summary(std::ostream& out, const FittedModel& model);

// The table of every channel's change at once and answered (steady state / after H / cumulative). Monte
// Carlo (the default): median and interval of the SAME draws as the live twin's bounded answer, so every
// point lies inside its interval. Delta method: the effect at the posterior mean with first-order intervals.
void print_intervention(std::ostream& out, const FittedModel& model, const analysis::InterventionQuery& query,
                        const analysis::UncertainEffect& effect, const analysis::BoundedAnswer& answer,
                        const analysis::UncertaintyOptions& options);

// CSV: n, then the counterfactual of every channel, then "<name> (observed)" columns, all in original units
// (shortest round-trip number text). counterfactual/observed: rows from..from+rows-1.
void write_counterfactual_csv(std::ostream& out, const std::vector<std::string>& names, int from,
                              const Eigen::MatrixXd& counterfactual, const Eigen::MatrixXd& observed);

// The bounded answer (steady state / after H snapshots / refused, bounded_answer.hpp): one line per channel
// with horizon, interval, confidence and stability, in the CSV's units and percent of the last row's level.
// log_levels: the CSV holds log levels (as the twin's log_transform): effects in percent of the level, with
// the live twin's one line (effect_units.hpp, effect_unknown_reason: an interval wider than a factor of 10 in
// level, or reaching beyond +-1000 %, is "effect unknown" with the reason). Otherwise percent of the level at
// --at when it is positive (the same line); when it is not, "effect unknown" with that reason. Every line ends
// with the effect in the CSV's own units.
void print_bounded_answer(std::ostream& out, const FittedModel& model, const analysis::InterventionQuery& query,
                          const analysis::BoundedAnswer& answer, bool log_levels = false);
void print_recommendations(std::ostream& out, const FittedModel& model, int target,
                           const std::vector<analysis::Recommendation>& recs);

// RFC 4180 quoting when needed.
std::string csv_field(const std::string& text);

}  // namespace causal::whatif
