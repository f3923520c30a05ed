// The one rule that turns the estimator's per-outcome reports of one index into the alarm engine's
// Observation. alarm-recommender (from CausalFactorBatch messages) and the offline chain
// (condition_alarm_chain.hpp, from the estimator pipeline's reports) both call it, so the engine sees the
// same observation whichever way the reports travelled.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "causal/alarms/observation.hpp"

namespace causal::alarms {

// What the estimator reports for one outcome k at one index (one OutcomeFactors block of a CausalFactorBatch, without DDS).
struct OutcomeReport {
  Eigen::VectorXd factors, factor_std;  // outcome k's factors and their standard deviations
  std::uint64_t innovation_count = 0;   // filter updates since the previous report (0: nothing fresh)
  double nis_mean = 0.0;                // mean e^2 / S over those updates
  double last_innovation = 0.0;         // e and S at the report's index
  double last_innovation_variance = 0.0;
};

// Observation of one index from the G outcome reports (outcome order): factors and standard deviations
// concatenated outcome-major; e_k and S_k only where outcome k had an update since its previous report
// (otherwise NaN: "no value for this channel now", e.g. a rejected sample); at sample level also the
// mean NIS per outcome. Features and the discontinuity flag come from the condition vector of the same
// time and are joined by the caller.
Observation observation_from_outcomes(std::uint64_t index, std::int64_t time_ns,
                                      const std::vector<OutcomeReport>& outcomes, bool sample_level);

}  // namespace causal::alarms
