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

void print_intervention(std::ostream& out, const FittedModel& model, const analysis::InterventionQuery& query,
                        const analysis::UncertainEffect& effect, const analysis::UncertaintyOptions& options);

// CSV: n, then the counterfactual of every channel, then "<name> (observed)" columns, all in original units
// (shortest round-trip number text). counterfactual/observed: rows from..from+rows-1.
void write_counterfactual_csv(std::ostream& out, const std::vector<std::string>& names, int from,
                              const Eigen::MatrixXd& counterfactual, const Eigen::MatrixXd& observed);

// The bounded answer (steady state / after H snapshots / refused, bounded_answer.hpp): one line per channel
// with horizon, interval, confidence and stability, in the CSV's units and percent of the last row's level.
void print_bounded_answer(std::ostream& out, const FittedModel& model, const analysis::InterventionQuery& query,
                          const analysis::BoundedAnswer& answer);
void print_recommendations(std::ostream& out, const FittedModel& model, int target,
                           const std::vector<analysis::Recommendation>& recs);

// RFC 4180 quoting when needed.
std::string csv_field(const std::string& text);

}  // namespace causal::whatif
