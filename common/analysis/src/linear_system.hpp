// Internal: the solves every analysis needs, with one definition of "singular" and "unstable".
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include <vector>

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

// Reduced-form companion matrix (top block row (I - A0)^{-1} A_l, identity below) from a factorisation of
// (I - A0) already made: the same matrix companion_matrix() builds, without a second LU.
Eigen::MatrixXd companion_from(const InstantaneousSolve& solve, const std::vector<Eigen::MatrixXd>& lags);

// True only when rho(m) < bound is PROVED without an eigen-decomposition: rho(m) <= ||m^k||^(1/k) for every
// induced norm (Gelfand), tried with the 1- and inf-norms for k = 1, 2, 4, .., 1024 by repeated squaring, with
// the rounding of the squarings bounded (||fl(P P) - P P|| <= 2 n eps ||P||^2) and added. False means "not
// proved" (then compute spectral_radius()); a Monte Carlo draw of a settling model usually needs no
// Hessenberg/Schur iteration at all, which was most of a what-if draw's cost at 20 channels.
bool radius_proved_below(const Eigen::MatrixXd& m, double bound);

// The same squarings, also trying the other side: rho(m) >= bound is PROVED when |tr(m^k)| >= n bound^k, as
// n rho^k >= |sum of the k-th powers of the eigenvalues| = |tr(m^k)| (rounding of the squarings bounded and
// subtracted). A posterior draw of a trending model (a self-lag above 1) is proved unstable in a few squarings
// instead of an eigen-decomposition: on IMS test 2 at 20 channels about 9 in 10 advice draws are such, and the
// Hessenberg/Schur iteration of their companion matrices was the largest part of the advice's CPU.
// none: neither proved (then compute spectral_radius()).
enum class RadiusProof { below, at_or_above, none };
RadiusProof prove_radius(const Eigen::MatrixXd& m, double bound, bool try_above);

}  // namespace causal::analysis::detail
