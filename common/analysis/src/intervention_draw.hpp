// Internal: the what-if of one Monte Carlo draw (bounded_answer.cpp), where only "does it settle" matters and
// not the exact spectral radius, so stability proved by norms of companion powers (or instability by their
// traces) skips the eigenvalues.
#pragma once

#include "causal/analysis/intervention.hpp"
#include "causal/analysis/structural_model.hpp"

namespace causal::analysis::detail {

// predict_intervention() with the same status, effects and path; only spectral_radius differs: when the
// system after n0 is proved to settle (or, with prove_unstable, not to settle) it is the bound 1 - 1e-9, not
// the radius itself. model_settles = false
// (settles(model) already computed false) for a sustained shift: status unstable with the same immediate
// effect and path, no dynamics check and no steady state (a draw whose model does not settle counts as
// unstable whatever its intervened system does). An impulse ignores it (its system after n0 IS the model).
InterventionEffect predict_intervention_draw(const StructuralModel& model, const InterventionQuery& query,
                                             bool model_settles = true, bool prove_unstable = true);

// check_dynamics(model).spectral_radius < 1 - 1e-9 (false when (I - A0) is singular or the model non-finite),
// without the eigenvalues where the norms (or, with prove_unstable, the traces) of companion powers prove it.
// prove_unstable = false is the way before that proof (DrawSharing::per_query, the reference of the bench).
bool settles(const StructuralModel& model, bool prove_unstable = true);

}  // namespace causal::analysis::detail
