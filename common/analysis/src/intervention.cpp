#include "causal/analysis/intervention.hpp"

#include "intervention_draw.hpp"
#include "linear_system.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

namespace causal::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::MatrixXd lag_sum(const StructuralModel& model) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(model.channels(), model.channels());
  for (const auto& a : model.lags) s += a;
  return s;
}

// sum_l A_l d[t-l] over the rows of `path` already computed (d before n0 is 0).
Eigen::VectorXd lagged_drive(const StructuralModel& model, const Eigen::MatrixXd& path, int t) {
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(model.channels());
  for (int l = 1; l <= model.lag_order() && t - l >= 0; ++l) {
    rhs.noalias() += model.lags[static_cast<std::size_t>(l - 1)] * path.row(t - l).transpose();
  }
  return rhs;
}

// The dynamics of the system that runs after n0, from the (I - A0) factorisation predict() already has. Exact
// (check_dynamics) unless `exact_radius` is false and the norms of companion powers prove it settles, or (with
// prove_unstable) the traces of its powers prove it does not; the radius is then that bound (1 - 1e-9), which is
// all a Monte Carlo draw needs.
DynamicsCheck dynamics_after(const StructuralModel& after, const detail::InstantaneousSolve& solve, bool exact_radius,
                             bool prove_unstable) {
  if (exact_radius || !solve.ok()) return check_dynamics(after);
  const Eigen::MatrixXd c = detail::companion_from(solve, after.lags);
  const detail::RadiusProof proof = detail::prove_radius(c, detail::kUnstableRadius, prove_unstable);
  if (proof == detail::RadiusProof::none) return check_dynamics(after);
  DynamicsCheck d;
  d.rcond = solve.rcond();
  d.spectral_radius = detail::kUnstableRadius;
  if (proof == detail::RadiusProof::at_or_above) {
    d.status = AnalysisStatus::unstable;
    d.message = "companion spectral radius proved >= 1 - 1e-9: the system does not settle, there is no steady state";
  }
  return d;
}

// skip_dynamics (sustained only): the caller already knows the model itself does not settle, so the draw is
// unstable whatever the intervened system does; its dynamics (the eigenvalue fallback where the norms prove
// nothing, most of a draw's cost on trending data) and the steady state are not computed.
InterventionEffect predict(const StructuralModel& model, const InterventionQuery& query, bool exact_radius,
                           bool skip_dynamics = false, bool prove_unstable = false) {
  validate_model(model);
  const int g = model.channels();
  const int j = query.channel;
  if (j < 0 || j >= g) {
    throw std::invalid_argument("intervention channel " + std::to_string(j) + " outside 0.." + std::to_string(g - 1));
  }
  if (query.horizon < 0) throw std::invalid_argument("intervention horizon must be >= 0");
  const bool sustained = query.kind == InterventionKind::sustained;

  InterventionEffect effect;
  effect.immediate = Eigen::VectorXd::Constant(g, kNaN);
  effect.steady_state = Eigen::VectorXd::Constant(g, kNaN);
  effect.cumulative = sustained ? Eigen::VectorXd() : Eigen::VectorXd::Constant(g, kNaN);
  effect.path = Eigen::MatrixXd::Constant(query.horizon, g, kNaN);
  effect.spectral_radius = kNaN;

  if (!std::isfinite(query.delta) || !all_finite(model)) {
    effect.status = AnalysisStatus::non_finite_input;
    effect.message = "non-finite intervention size or model coefficients";
    return effect;
  }

  const StructuralModel cut = graph_surgery(model, {j});
  const detail::InstantaneousSolve cut_solve(cut.a0);
  if (!cut_solve.ok()) {
    effect.status = AnalysisStatus::not_identifiable;
    effect.message = "with channel " + std::to_string(j) +
                     " held, (I - A0) of the remaining channels is singular: instantaneous links among them form a "
                     "loop with gain 1; the effect is not identifiable (restrict to an acyclic causal graph)";
    return effect;
  }
  Eigen::VectorXd forcing = Eigen::VectorXd::Zero(g);
  forcing(j) = query.delta;
  effect.immediate = cut_solve.solve(forcing);  // (W2)
  effect.immediate(j) = query.delta;            // row j of (I - A0c) is e_j^T: exact by construction

  // Steady state / cumulative need the system that runs after n0 to be stable.
  const StructuralModel& after = sustained ? cut : model;
  // For a sustained shift the system after n0 is the cut one: its (I - A0c) is already factorised.
  std::optional<detail::InstantaneousSolve> impulse_solve;
  if (!sustained) impulse_solve.emplace(after.a0);
  const detail::InstantaneousSolve& after_solve = sustained ? cut_solve : *impulse_solve;
  DynamicsCheck dynamics;
  if (skip_dynamics && sustained) {
    dynamics.status = AnalysisStatus::unstable;
    dynamics.spectral_radius = kNaN;
    dynamics.message = "the model itself does not settle, there is no steady state";
  } else {
    dynamics = dynamics_after(after, after_solve, exact_radius, prove_unstable);
  }
  effect.spectral_radius = dynamics.spectral_radius;

  // Path (W1) or the impulse recursion; rows stay NaN if the post-n0 system cannot be solved.
  if (query.horizon > 0) {
    effect.path.row(0) = effect.immediate.transpose();
    if (sustained || dynamics.status != AnalysisStatus::not_identifiable) {
      for (int t = 1; t < query.horizon; ++t) {
        Eigen::VectorXd rhs = lagged_drive(after, effect.path, t);
        if (sustained) rhs += forcing;
        effect.path.row(t) = after_solve.solve(rhs).transpose();
      }
    }
  }

  if (dynamics.status != AnalysisStatus::ok) {
    effect.status = dynamics.status;
    effect.message = std::string(sustained ? "intervened system: " : "original system: ") + dynamics.message;
    return effect;
  }
  const Eigen::MatrixXd i_minus_a0 = Eigen::MatrixXd::Identity(g, g) - after.a0;
  const detail::SquareSolve long_run(i_minus_a0 - lag_sum(after));
  if (!long_run.ok()) {
    // Stable yet (I - A0 - sum A) ill-conditioned: a root very close to 1, treat as not settling.
    effect.status = AnalysisStatus::unstable;
    effect.message = "(I - A0 - sum A_l) is numerically singular: a root at 1, no steady state";
    return effect;
  }
  if (sustained) {
    effect.steady_state = long_run.solve(forcing);  // (W3)
    effect.steady_state(j) = query.delta;
  } else {
    effect.steady_state.setZero();
    effect.cumulative = long_run.solve(i_minus_a0 * effect.immediate);  // (W4)
  }
  return effect;
}

}  // namespace

const char* to_string(InterventionKind kind) {
  return kind == InterventionKind::impulse ? "impulse" : "sustained";
}

InterventionEffect predict_intervention(const StructuralModel& model, const InterventionQuery& query) {
  return predict(model, query, /*exact_radius=*/true);
}

namespace detail {

InterventionEffect predict_intervention_draw(const StructuralModel& model, const InterventionQuery& query,
                                             bool model_settles, bool prove_unstable) {
  return predict(model, query, /*exact_radius=*/false, /*skip_dynamics=*/!model_settles, prove_unstable);
}

bool settles(const StructuralModel& model, bool prove_unstable) {
  if (!all_finite(model)) return false;
  const InstantaneousSolve solve(model.a0);
  if (!solve.ok()) return false;
  const Eigen::MatrixXd c = companion_from(solve, model.lags);
  const RadiusProof proof = prove_radius(c, kUnstableRadius, prove_unstable);
  if (proof != RadiusProof::none) return proof == RadiusProof::below;
  return spectral_radius(c) < kUnstableRadius;
}

}  // namespace detail
}  // namespace causal::analysis
