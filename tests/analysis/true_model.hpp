// The structural model of a simulated SVAR's true coefficients: what a perfect fit would return, so that the
// what-if and counterfactual answers can be checked against re-simulating the true system.
#pragma once

#include "causal/analysis/structural_model.hpp"
#include "svar_sim.hpp"

namespace causal::analysis::test {

inline StructuralModel model_of(const TrueSvar& s) {
  StructuralModel m;
  m.a0 = s.a0;
  m.lags = s.lags;
  return m;
}

}  // namespace causal::analysis::test
