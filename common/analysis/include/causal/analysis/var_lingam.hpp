// VAR-LiNGAM (Hyvärinen, Zhang, Shimizu, Hoyer, JMLR 11, 2010): causal order of the instantaneous links.
//   1. fit the reduced-form VAR(M) by least squares (var_fit.hpp):  y[n] = c + sum Phi_l y[n-l] + u[n]
//   2. DirectLiNGAM on the residuals u (direct_lingam.hpp):          u = B0 u + e
//   3. structural lags B_l = (I - B0) Phi_l  (from (I - B0) y[n] = (I - B0)c + sum (I - B0) Phi_l y[n-l] + e)
// The order restricts the Kalman filter: j may cause k instantaneously only if j precedes k, which
// makes the per-outcome regressions one identified structural model (see causal_graph.hpp).
#pragma once

#include "causal/analysis/structural_model.hpp"
#include "causal/analysis/var_fit.hpp"

#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <vector>

namespace causal::analysis {

struct VarLingamOptions {
  int lag_order = 1;
  bool intercept = true;
  // |B0(k, j)| below this removes the link j -> k from the mask (0 keeps every order-consistent link).
  // Pruning makes the filter leaner but can drop a weak true link; the order alone is the safe default.
  double prune_threshold = 0.0;
};

struct VarLingamResult {
  VarFit var;                            // step 1
  std::vector<int> order;                // causes first
  Eigen::MatrixXd b0;                    // G x G instantaneous structural coefficients (step 2)
  std::vector<Eigen::MatrixXd> lagged;   // B_1..B_M (step 3)
  Eigen::VectorXd intercept;             // (I - B0) c
  Eigen::VectorXd noise_variance;        // per channel variance of e: a starting value for the filter's r
  std::vector<std::vector<bool>> instantaneous_allowed;  // [k][j]: j precedes k (and survived pruning)

  // (S1) with A0 = B0 and A_l = B_l (self lags included).
  StructuralModel model() const;
  // spec with instantaneous_allowed = this mask (intersected with spec's own mask if it has one).
  estimation::ModelSpec restrict(estimation::ModelSpec spec) const;
};

// samples: N x G calibration window. Throws std::invalid_argument as fit_var_least_squares /
// direct_lingam do (too few samples, constant residual channel, ...).
VarLingamResult var_lingam(const Eigen::MatrixXd& samples, const VarLingamOptions& options = {});

}  // namespace causal::analysis
