#include "posterior_draws.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace causal::analysis::detail {
namespace {

// Symmetric square root S with S S^T = P; negative eigenvalues (rounding, fixed factors) clipped to 0 so a
// semi-definite block still gives valid draws.
Eigen::MatrixXd psd_sqrt(const Eigen::MatrixXd& p) {
  if (p.size() == 0) return p;  // fully masked outcome: no factors
  const Eigen::MatrixXd sym = 0.5 * (p + p.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym);
  if (es.info() != Eigen::Success) throw std::invalid_argument("factor covariance block has no eigen-decomposition");
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

}  // namespace

PosteriorSampler::PosteriorSampler(const estimation::SvarLayout& layout, const FactorPosterior& posterior, std::uint64_t seed)
    : layout_(layout), posterior_(posterior), rng_(seed), x_(posterior.mean.size()) {
  for (const auto& block : posterior.blocks) roots_.push_back(psd_sqrt(block));
}

const Eigen::VectorXd& PosteriorSampler::next() {
  for (int k = 0; k < layout_.channels(); ++k) {
    const int fk = layout_.factor_count(k);
    Eigen::VectorXd z(fk);
    for (int i = 0; i < fk; ++i) z(i) = normal_(rng_);
    x_.segment(layout_.offset(k), fk) =
        posterior_.mean.segment(layout_.offset(k), fk) + roots_[static_cast<std::size_t>(k)] * z;
  }
  return x_;
}

double percentile(const std::vector<double>& sorted, double p) {
  const double pos = p * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double w = pos - static_cast<double>(lo);
  return sorted[lo] * (1.0 - w) + sorted[hi] * w;
}

}  // namespace causal::analysis::detail
