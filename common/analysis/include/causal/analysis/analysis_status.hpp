// Outcome of an analysis query (what-if, counterfactual, uncertainty draw).
//
// House rule: configuration errors (bad channel index, wrong shapes) throw std::invalid_argument; a query
// that is well-formed but has no answer for THIS model (the intervened system cannot be solved or does not
// settle) is reported with one of these statuses and a message, never an exception.
#pragma once

namespace causal::analysis {

enum class AnalysisStatus {
  ok,
  // (I - A0_cut) is singular (or numerically so): the instantaneous equations have no unique solution,
  // e.g. instantaneous links running both ways with a loop gain of 1. The per-outcome regressions then do
  // not define one structural model.
  not_identifiable,
  // Spectral radius of the companion matrix of the (intervened) system >= 1: there is no steady state.
  unstable,
  // A non-finite value in the data window or in the factors.
  non_finite_input,
};

const char* to_string(AnalysisStatus status);

}  // namespace causal::analysis
