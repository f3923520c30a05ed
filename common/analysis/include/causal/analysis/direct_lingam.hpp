// DirectLiNGAM (Shimizu et al., JMLR 12, 2011) with the pairwise likelihood-ratio measure of
// Hyvärinen & Smith (JMLR 14, 2013), entropies by the maximum-entropy approximation (Hyvärinen 1998).
//
// Model: x = B0 x + e with B0 permutable to strictly lower triangular and e independent NON-Gaussian.
// Step: among the remaining variables U pick the most exogenous one m, then replace every other x_i by
// its residual after regressing on x_m; repeat. The exogeneity score of i is
//   T(i) = sum_{j in U, j != i} min(0, R(i, j))^2                                          (L1)
//   R(i, j) = H(x_j) + H(r_i^(j)) - H(x_i) - H(r_j^(i))                                     (L2)
// with standardized variables and standardized residuals r_i^(j) = x_i - rho x_j. R(i, j) > 0 favours
// x_i -> x_j (the log-likelihood ratio of Hyvärinen & Smith, Sec. 2.5). m = argmin T.
//
// Limits: needs non-Gaussian disturbances (with Gaussian e every order is equally likely and the result
// is arbitrary), enough samples (hundreds), and no hidden common causes.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace causal::analysis {

// Differential entropy of a standardized variable, maximum-entropy approximation:
//   H(u) ~ (1 + log 2 pi)/2 - k1 (E[log cosh u] - gamma)^2 - k2 (E[u exp(-u^2/2)])^2           (L3)
// k1 = 79.047, k2 = 7.4129, gamma = 0.37457. Equals the Gaussian entropy for Gaussian u (to sampling error)
// and is smaller for any other distribution.
double entropy_approximation(const Eigen::VectorXd& standardized);

// (L2) for two raw variables (standardized inside). > 0: evidence for xi -> xj.
double pairwise_likelihood_ratio(const Eigen::VectorXd& xi, const Eigen::VectorXd& xj);

struct DirectLingamResult {
  std::vector<int> order;   // causal order, exogenous first
  Eigen::MatrixXd b0;       // G x G, b0(k, j) != 0 only if j precedes k: OLS of x_k on its predecessors
  Eigen::MatrixXd disturbances;  // N x G, e = x_c - x_c B0^T (x_c = column-centered x)
};

// x: N x G, rows = samples, all finite. Throws std::invalid_argument for G < 1, N < 10, non-finite
// values or a (numerically) constant column.
DirectLingamResult direct_lingam(const Eigen::MatrixXd& x);

}  // namespace causal::analysis
