// Uncertainty of what-if effects from the factor covariance.
//
// The filter's factor covariance is block-diagonal by outcome (each outcome is a separate filter), so
// factors of different outcomes are drawn independently. Two methods:
//  * monte_carlo: draw x ~ N(mean, blockdiag(P_k)) (fixed seed, `draws` draws), rebuild (S1), compute the
//    effect; the interval is the (1-c)/2 .. (1+c)/2 empirical percentile. Draws whose intervened system
//    is unstable / singular have no effect to report: they are counted in draws_rejected and left out,
//    so the interval is CONDITIONAL on the system settling (a large rejected share is itself a warning).
//  * delta_method: first-order propagation  Var f ~ sum_k J_k P_k J_k^T  with J by central differences;
//    interval point -/+ z_{(1+c)/2} sd. Cheap, symmetric, poor when the effect is strongly non-linear in
//    the factors (near-singular or near-unstable systems, where (W3) blows up).
#pragma once

#include "causal/estimation/normal_quantile.hpp"

#include "causal/analysis/intervention.hpp"
#include "causal/analysis/structural_model.hpp"

#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <cstdint>

namespace causal::analysis {

enum class IntervalMethod { monte_carlo, delta_method };

struct UncertaintyOptions {
  double coverage = 0.90;  // central interval probability, in (0, 1)
  int draws = 2000;        // Monte Carlo draws
  std::uint64_t seed = 20240611;
  IntervalMethod method = IntervalMethod::monte_carlo;
  double relative_step = 1e-6;  // delta method: h_i = relative_step * max(1, |x_i|)
};

struct EffectInterval {
  Eigen::VectorXd lower;    // G
  Eigen::VectorXd upper;    // G
  Eigen::VectorXd std_dev;  // G: sample sd of the draws (MC) or first-order sd (delta method)
};

struct UncertainEffect {
  InterventionEffect point;  // effect at the posterior mean (status/message of the query live here)
  EffectInterval immediate;
  EffectInterval steady_state;
  EffectInterval cumulative;  // impulse only; size-0 vectors for a sustained shift
  double coverage = 0.0;
  IntervalMethod method = IntervalMethod::monte_carlo;
  int draws_used = 0;      // MC: draws with an ok effect
  int draws_rejected = 0;  // MC: draws with an unstable / singular / non-finite system
  // false when no interval could be formed (point not ok, < 2 usable draws, or a delta-method
  // perturbation failed); the intervals are then NaN.
  bool interval_valid = false;
};

// Throws std::invalid_argument for coverage outside (0,1), draws < 2, non-positive step, or a posterior
// that does not match the layout.
UncertainEffect predict_intervention_with_uncertainty(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                                      const InterventionQuery& query,
                                                      const UncertaintyOptions& options = {});

// Standard normal quantile Phi^{-1}(p), p in (0, 1) (Acklam's rational approximation refined by one
// Halley step on erfc; |error| < 1e-12).
using estimation::normal_quantile;  // common/estimation: <causal/estimation/normal_quantile.hpp>

const char* to_string(IntervalMethod method);

}  // namespace causal::analysis
