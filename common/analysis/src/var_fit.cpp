#include "causal/analysis/var_fit.hpp"

#include <Eigen/QR>
#include <stdexcept>
#include <string>

namespace causal::analysis {

VarFit fit_var_least_squares(const Eigen::MatrixXd& samples, int lag_order, bool intercept) {
  if (lag_order < 1) throw std::invalid_argument("VAR fit: lag_order must be >= 1");
  const int g = static_cast<int>(samples.cols());
  if (g < 1) throw std::invalid_argument("VAR fit: no channels");
  const int n_rows = static_cast<int>(samples.rows());

  VarFit fit;
  fit.lag_order = lag_order;
  fit.has_intercept = intercept;
  std::vector<bool> finite_row(static_cast<std::size_t>(n_rows));
  for (int n = 0; n < n_rows; ++n) finite_row[n] = samples.row(n).allFinite();
  for (int n = lag_order; n < n_rows; ++n) {
    bool ok = true;
    for (int l = 0; l <= lag_order && ok; ++l) ok = finite_row[n - l];
    if (ok) {
      fit.rows_used.push_back(n);
    } else {
      ++fit.rows_skipped;
    }
  }
  const int t = static_cast<int>(fit.rows_used.size());
  const int p = (intercept ? 1 : 0) + g * lag_order;
  if (t < p + g + 2) {
    throw std::invalid_argument("VAR fit: " + std::to_string(t) + " usable samples for " + std::to_string(p) +
                                " regressors per channel; need at least " + std::to_string(p + g + 2));
  }
  // Design X (t x p): [1, y[n-1]^T, ..., y[n-M]^T]; targets Y (t x g).
  Eigen::MatrixXd x(t, p);
  Eigen::MatrixXd y(t, g);
  for (int r = 0; r < t; ++r) {
    const int n = fit.rows_used[static_cast<std::size_t>(r)];
    int c = 0;
    if (intercept) x(r, c++) = 1.0;
    for (int l = 1; l <= lag_order; ++l, c += g) x.block(r, c, 1, g) = samples.row(n - l);
    y.row(r) = samples.row(n);
  }
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(x);
  const Eigen::MatrixXd beta = cod.solve(y);  // p x g
  fit.residuals = y - x * beta;
  int c = 0;
  fit.intercept = Eigen::VectorXd::Zero(g);
  if (intercept) fit.intercept = beta.row(c++).transpose();
  for (int l = 1; l <= lag_order; ++l, c += g) fit.coefficients.push_back(beta.middleRows(c, g).transpose());
  return fit;
}

}  // namespace causal::analysis
