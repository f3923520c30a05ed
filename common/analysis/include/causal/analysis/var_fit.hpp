// Least-squares reduced-form VAR(M) on a calibration window:
//   y[n] = c + sum_{l=1..M} Phi_l y[n-l] + u[n]                                              (V1)
// The residuals u[n] are the input of DirectLiNGAM in VAR-LiNGAM (u = (I - B0)^{-1} e).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace causal::analysis {

struct VarFit {
  int lag_order = 0;
  bool has_intercept = true;
  Eigen::VectorXd intercept;                  // G; zeros without intercept
  std::vector<Eigen::MatrixXd> coefficients;  // Phi_1..Phi_M, each G x G, Phi_l(k, j) = effect of y_j[n-l] on y_k[n]
  Eigen::MatrixXd residuals;                  // one row per usable sample, G columns
  std::vector<int> rows_used;                 // sample index n of each residual row
  int rows_skipped = 0;                       // samples whose window (y[n], y[n-1..n-M]) had a non-finite value
};

// Complete-orthogonal-decomposition least squares (minimum-norm if the design is rank deficient).
// Samples whose window holds a non-finite value are skipped and counted. Throws std::invalid_argument when
// lag_order < 1 or fewer than G*M + G + 2 usable samples remain.
VarFit fit_var_least_squares(const Eigen::MatrixXd& samples, int lag_order, bool intercept = true);

}  // namespace causal::analysis
