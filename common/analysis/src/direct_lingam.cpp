#include "causal/analysis/direct_lingam.hpp"

#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace causal::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;

// log cosh without overflow: |u| + log1p(exp(-2|u|)) - log 2.
double log_cosh(double u) {
  const double a = std::abs(u);
  return a + std::log1p(std::exp(-2.0 * a)) - std::log(2.0);
}

// Population-standardized copy (mean 0, variance 1 with divisor N, as in the reference algorithm).
Eigen::VectorXd standardize(const Eigen::VectorXd& v) {
  const Eigen::VectorXd c = v.array() - v.mean();
  const double sd = std::sqrt(c.squaredNorm() / static_cast<double>(c.size()));
  if (!(sd > 0.0)) return Eigen::VectorXd::Zero(v.size());
  return c / sd;
}

// Residual of a on b (both centered): a - cov(a,b)/var(b) b.
Eigen::VectorXd residual(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double vb = b.squaredNorm();
  if (!(vb > 0.0)) return a;
  return a - (a.dot(b) / vb) * b;
}

}  // namespace

double entropy_approximation(const Eigen::VectorXd& u) {
  constexpr double k1 = 79.047;
  constexpr double k2 = 7.4129;
  constexpr double gamma = 0.37457;
  const double n = static_cast<double>(u.size());
  double mean_log_cosh = 0.0;
  double mean_gauss = 0.0;
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    mean_log_cosh += log_cosh(u(i));
    mean_gauss += u(i) * std::exp(-0.5 * u(i) * u(i));
  }
  mean_log_cosh /= n;
  mean_gauss /= n;
  return 0.5 * (1.0 + std::log(2.0 * kPi)) - k1 * (mean_log_cosh - gamma) * (mean_log_cosh - gamma) -
         k2 * mean_gauss * mean_gauss;
}

double pairwise_likelihood_ratio(const Eigen::VectorXd& xi, const Eigen::VectorXd& xj) {
  const Eigen::VectorXd si = standardize(xi);
  const Eigen::VectorXd sj = standardize(xj);
  const Eigen::VectorXd ri_j = standardize(residual(si, sj));
  const Eigen::VectorXd rj_i = standardize(residual(sj, si));
  return entropy_approximation(sj) + entropy_approximation(ri_j) - entropy_approximation(si) -
         entropy_approximation(rj_i);
}

DirectLingamResult direct_lingam(const Eigen::MatrixXd& x) {
  const int g = static_cast<int>(x.cols());
  const Eigen::Index n = x.rows();
  if (g < 1) throw std::invalid_argument("DirectLiNGAM: no variables");
  if (n < 10) throw std::invalid_argument("DirectLiNGAM: need at least 10 samples, got " + std::to_string(n));
  if (!x.allFinite()) throw std::invalid_argument("DirectLiNGAM: non-finite values in the input");

  const Eigen::MatrixXd centered = x.rowwise() - x.colwise().mean();
  for (int k = 0; k < g; ++k) {
    const double var = centered.col(k).squaredNorm() / static_cast<double>(n);
    const double scale = std::max(1.0, x.col(k).cwiseAbs().maxCoeff());
    if (!(var > 1e-24 * scale * scale)) {
      throw std::invalid_argument("DirectLiNGAM: variable " + std::to_string(k) + " is constant");
    }
  }

  DirectLingamResult result;
  Eigen::MatrixXd work = centered;  // columns of the remaining variables get regressed on each chosen one
  std::vector<int> remaining;
  for (int k = 0; k < g; ++k) remaining.push_back(k);
  while (!remaining.empty()) {
    int best = remaining.front();
    if (remaining.size() > 1) {
      // Standardize once per round: R(i, j) uses standardized inputs (L2).
      std::vector<Eigen::VectorXd> std_cols(static_cast<std::size_t>(g));
      std::vector<double> h(static_cast<std::size_t>(g), 0.0);
      for (int k : remaining) {
        std_cols[k] = standardize(work.col(k));
        h[k] = entropy_approximation(std_cols[k]);
      }
      double best_score = std::numeric_limits<double>::infinity();
      for (int i : remaining) {
        double score = 0.0;  // (L1)
        for (int j : remaining) {
          if (i == j) continue;
          const double r = h[j] + entropy_approximation(standardize(residual(std_cols[i], std_cols[j]))) - h[i] -
                           entropy_approximation(standardize(residual(std_cols[j], std_cols[i])));
          const double neg = std::min(0.0, r);
          score += neg * neg;
        }
        if (score < best_score) {
          best_score = score;
          best = i;
        }
      }
    }
    result.order.push_back(best);
    std::vector<int> rest;
    for (int k : remaining) {
      if (k == best) continue;
      work.col(k) = residual(work.col(k), work.col(best));
      rest.push_back(k);
    }
    remaining = rest;
  }

  // B0 by least squares of each variable on its predecessors in the order.
  result.b0 = Eigen::MatrixXd::Zero(g, g);
  for (int p = 1; p < g; ++p) {
    const int k = result.order[static_cast<std::size_t>(p)];
    Eigen::MatrixXd design(n, p);
    for (int q = 0; q < p; ++q) design.col(q) = centered.col(result.order[static_cast<std::size_t>(q)]);
    const Eigen::VectorXd coef = design.colPivHouseholderQr().solve(centered.col(k));
    for (int q = 0; q < p; ++q) result.b0(k, result.order[static_cast<std::size_t>(q)]) = coef(q);
  }
  result.disturbances = centered - centered * result.b0.transpose();
  return result;
}

}  // namespace causal::analysis
