// Internal: the solves every analysis needs, with one definition of "singular" and "unstable".
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

namespace causal::analysis::detail {

// (I - A0) with reciprocal condition below this is treated as singular: the instantaneous equations then
// amplify rounding by > 1e10, so any "effect" computed from them is noise.
constexpr double kSingularRcond = 1e-10;
// Companion spectral radius at or above this has no steady state (unit root or explosive).
constexpr double kUnstableRadius = 1.0 - 1e-9;

// LU of a square matrix (e.g. I - A0 - sum A_l): solves m y = b without forming the inverse; ok() is false
// when m is non-finite or singular by kSingularRcond.
class SquareSolve {
 public:
  explicit SquareSolve(const Eigen::MatrixXd& m);
  bool ok() const { return ok_; }
  double rcond() const { return rcond_; }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const { return lu_.solve(rhs); }

 private:
  Eigen::FullPivLU<Eigen::MatrixXd> lu_;
  bool ok_ = false;
  double rcond_ = 0.0;
};

// The same for (I - A0), the instantaneous part of the structural equations: solves (I - A0) y = b.
class InstantaneousSolve : public SquareSolve {
 public:
  explicit InstantaneousSolve(const Eigen::MatrixXd& a0)
      : SquareSolve(Eigen::MatrixXd::Identity(a0.rows(), a0.cols()) - a0) {}
};

// max |eigenvalue|; 0 for an empty matrix.
double spectral_radius(const Eigen::MatrixXd& m);

}  // namespace causal::analysis::detail
