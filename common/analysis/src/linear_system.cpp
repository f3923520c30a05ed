#include "linear_system.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace causal::analysis::detail {

SquareSolve::SquareSolve(const Eigen::MatrixXd& m) : lu_(m) {
  if (!m.allFinite()) return;
  if (!lu_.isInvertible()) return;
  rcond_ = lu_.rcond();
  ok_ = std::isfinite(rcond_) && rcond_ >= kSingularRcond;
}

double spectral_radius(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 0.0;
  Eigen::EigenSolver<Eigen::MatrixXd> solver(m, /*computeEigenvectors=*/false);
  if (solver.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return solver.eigenvalues().cwiseAbs().maxCoeff();
}

}  // namespace causal::analysis::detail
