#include "linear_system.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
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

Eigen::MatrixXd companion_from(const InstantaneousSolve& solve, const std::vector<Eigen::MatrixXd>& lags) {
  const Eigen::Index m = static_cast<Eigen::Index>(lags.size());
  const Eigen::Index g = m > 0 ? lags.front().rows() : 0;
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(g * m, g * m);
  for (Eigen::Index l = 0; l < m; ++l) c.block(0, l * g, g, g) = solve.solve(lags[static_cast<std::size_t>(l)]);
  if (m > 1) c.block(g, 0, g * (m - 1), g * (m - 1)).setIdentity();
  return c;
}

RadiusProof prove_radius(const Eigen::MatrixXd& m, double bound, bool try_above) {
  if (m.size() == 0) return 0.0 < bound ? RadiusProof::below : RadiusProof::none;
  if (!m.allFinite() || !(bound > 0.0)) return RadiusProof::none;
  constexpr int kSquarings = 10;  // up to m^1024: a draw near a unit root (rho 0.99) is still proved
  const double n = static_cast<double>(m.rows());
  const double unit = 2.0 * n * std::numeric_limits<double>::epsilon();
  Eigen::MatrixXd p = m;
  double limit = bound;          // bound^k
  double err1 = 0.0, errinf = 0.0;  // bounds on ||P - m^k|| in the 1- and inf-norms (rounding of the squarings)
  for (int s = 0;; ++s) {
    const double n1 = p.cwiseAbs().colwise().sum().maxCoeff();
    const double ninf = p.cwiseAbs().rowwise().sum().maxCoeff();
    if (!std::isfinite(n1) || !std::isfinite(ninf)) return RadiusProof::none;
    // rho^k <= ||m^k|| <= ||P|| + ||P - m^k||
    if (std::min(n1 + err1, ninf + errinf) < limit) return RadiusProof::below;
    // n rho^k >= |tr m^k| >= |tr P| - |tr (P - m^k)|, and |tr E| <= n min(||E||_1, ||E||_inf) (each |E_ii| is at
    // most its column's and its row's absolute sum).
    if (try_above && std::abs(p.trace()) - n * std::min(err1, errinf) >= n * limit) return RadiusProof::at_or_above;
    if (s == kSquarings) return RadiusProof::none;
    err1 = unit * n1 * n1 + 2.0 * n1 * err1 + err1 * err1;
    errinf = unit * ninf * ninf + 2.0 * ninf * errinf + errinf * errinf;
    p = (p * p).eval();
    limit *= limit;
  }
}

bool radius_proved_below(const Eigen::MatrixXd& m, double bound) {
  return prove_radius(m, bound, /*try_above=*/false) == RadiusProof::below;
}

}  // namespace causal::analysis::detail
