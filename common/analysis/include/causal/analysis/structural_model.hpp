// Structural VAR assembled from the estimator's causal factors.
//
//   y[n] = A0 y[n] + sum_{l=1..M} A_l y[n-l] + e[n]                                  (S1)
//
// A0(k, j) = x_kj (instantaneous, zero diagonal), A_l(k, j) = xL{l}_kj, taken from the factor vector of
// SvarLayout (outcome-major). Factors the layout does not carry (masked links, self lags when
// include_self_lags = false) are structural zeros.
//
// LIMITS (read before trusting an answer):
//  * The estimator fits G separate regressions, one per outcome. They form ONE structural model only
//    when the instantaneous links are acyclic (a causal order, see causal_graph.hpp / var_lingam.hpp).
//    With links allowed both ways, (S1) is not identified from data: each regression is the best linear
//    predictor of y_k given the others, and stacking them can give an (I - A0) that is singular or
//    near-singular, or effects that are not causal. check_dynamics() reports singularity; it cannot
//    detect a merely wrong direction.
//  * The factors are time-varying (random walk); a StructuralModel is a snapshot at one sample.
//  * The factor covariance of the filter is block-diagonal by outcome (outcomes are filtered
//    independently), so cross-outcome correlations of the estimation errors are ignored (taken as 0).
#pragma once

#include "causal/analysis/analysis_status.hpp"

#include <causal/estimation/svar_kalman_filter.hpp>
#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace causal::analysis {

struct StructuralModel {
  Eigen::MatrixXd a0;                 // G x G, a0(k, j) = effect of y_j[n] on y_k[n]; diagonal 0
  std::vector<Eigen::MatrixXd> lags;  // M matrices G x G: lags[l-1](k, j) = effect of y_j[n-l] on y_k[n]

  int channels() const { return static_cast<int>(a0.rows()); }
  int lag_order() const { return static_cast<int>(lags.size()); }
};

// Zero model with G channels and M lags.
StructuralModel zero_model(int channels, int lag_order);
// Throws std::invalid_argument when a0 is not square, a lag matrix has another shape, or a0 has a
// non-zero diagonal.
void validate_model(const StructuralModel& model);
bool all_finite(const StructuralModel& model);

// Factor vector (layout order, size total_factors()) -> A0, A_1..A_M. Throws std::invalid_argument on
// a size mismatch.
StructuralModel assemble_structural_model(const estimation::SvarLayout& layout, const Eigen::VectorXd& factors);
// The inverse: the factors a layout would carry for this model (links outside the layout are dropped).
Eigen::VectorXd factors_from_model(const estimation::SvarLayout& layout, const StructuralModel& model);

// Factor estimate with its uncertainty at one sample.
struct FactorPosterior {
  Eigen::VectorXd mean;                 // total_factors(), layout order
  std::vector<Eigen::MatrixXd> blocks;  // per outcome k: factor_count(k) x factor_count(k) covariance
};

// Current estimate and per-outcome covariance of a running filter.
FactorPosterior posterior_from_filter(const estimation::SvarLayout& layout, const estimation::SvarKalmanFilter& filter);
// Diagonal blocks from standard deviations (e.g. a row of EstimationRun::std_devs); loses the
// within-outcome correlations, so intervals are only approximate.
FactorPosterior posterior_from_std_devs(const estimation::SvarLayout& layout, const Eigen::VectorXd& mean,
                                        const Eigen::VectorXd& std_devs);
// Throws std::invalid_argument when sizes disagree with the layout.
void validate_posterior(const estimation::SvarLayout& layout, const FactorPosterior& posterior);

// Graph surgery for do(y_j := ...): the equations of the `replaced` channels are removed, i.e. their
// rows of A0 and of every A_l are set to zero (the intervention then supplies y_j directly).
StructuralModel graph_surgery(const StructuralModel& model, const std::vector<int>& replaced);

// Is (S1) solvable for y[n] and does it settle?
struct DynamicsCheck {
  AnalysisStatus status = AnalysisStatus::ok;
  double rcond = 0.0;            // reciprocal condition estimate of (I - A0)
  double spectral_radius = 0.0;  // of the reduced-form companion matrix; NaN when not identifiable
  std::string message;
};
// (I - A0) numerically singular (rcond < 1e-10) -> not_identifiable; spectral radius of the companion
// matrix of B_l = (I - A0)^{-1} A_l >= 1 - 1e-9 -> unstable. Forced rows (from graph_surgery) are
// handled naturally: their rows of B_l are zero.
DynamicsCheck check_dynamics(const StructuralModel& model);

// Reduced-form companion matrix (GM x GM): top block row [B_1 .. B_M], identity below. Throws
// std::invalid_argument when (I - A0) is singular.
Eigen::MatrixXd companion_matrix(const StructuralModel& model);

}  // namespace causal::analysis
