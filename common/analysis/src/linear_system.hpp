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

// LU of (I - A0): solves (I - A0) y = b without forming the inverse.
class InstantaneousSolve {
 public:
  explicit InstantaneousSolve(const Eigen::MatrixXd& a0);
  bool ok() const { return ok_; }
  double rcond() const { return rcond_; }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const { return lu_.solve(rhs); }

 private:
  Eigen::FullPivLU<Eigen::MatrixXd> lu_;
  bool ok_ = false;
  double rcond_ = 0.0;
};

// Same, for a general square matrix (I - A0 - sum A_l).
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

// max |eigenvalue|; 0 for an empty matrix.
double spectral_radius(const Eigen::MatrixXd& m);

}  // namespace causal::analysis::detail
