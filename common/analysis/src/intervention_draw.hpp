// Internal: the what-if of one Monte Carlo draw (bounded_answer.cpp), where only "does it settle" matters and
// not the exact spectral radius, so stability proved by norms of companion powers skips the eigenvalues.
#pragma once

#include "causal/analysis/intervention.hpp"
#include "causal/analysis/structural_model.hpp"

namespace causal::analysis::detail {

// predict_intervention() with the same status, effects and path; only spectral_radius differs: when the
// system after n0 is proved to settle it is the bound 1 - 1e-9, not the radius itself.
InterventionEffect predict_intervention_draw(const StructuralModel& model, const InterventionQuery& query);

// check_dynamics(model).spectral_radius < 1 - 1e-9 (false when (I - A0) is singular or the model non-finite),
// without the eigenvalues where the norms prove it.
bool settles(const StructuralModel& model);

}  // namespace causal::analysis::detail
