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
// (check_dynamics) unless `exact_radius` is false and the norms of companion powers prove it settles; the radius
// is then that upper bound (< 1 - 1e-9), which is all a Monte Carlo draw needs.
DynamicsCheck dynamics_after(const StructuralModel& after, const detail::InstantaneousSolve& solve, bool exact_radius) {
  if (exact_radius || !solve.ok()) return check_dynamics(after);
  const Eigen::MatrixXd c = detail::companion_from(solve, after.lags);
  if (!detail::radius_proved_below(c, detail::kUnstableRadius)) return check_dynamics(after);
  DynamicsCheck d;
  d.rcond = solve.rcond();
  d.spectral_radius = detail::kUnstableRadius;
  return d;
}

InterventionEffect predict(const StructuralModel& model, const InterventionQuery& query, bool exact_radius) {
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
  const DynamicsCheck dynamics = dynamics_after(after, after_solve, exact_radius);
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

InterventionEffect predict_intervention_draw(const StructuralModel& model, const InterventionQuery& query) {
  return predict(model, query, /*exact_radius=*/false);
}

bool settles(const StructuralModel& model) {
  if (!all_finite(model)) return false;
  const InstantaneousSolve solve(model.a0);
  if (!solve.ok()) return false;
  const Eigen::MatrixXd c = companion_from(solve, model.lags);
  return radius_proved_below(c, kUnstableRadius) || spectral_radius(c) < kUnstableRadius;
}

}  // namespace detail
}  // namespace causal::analysis
