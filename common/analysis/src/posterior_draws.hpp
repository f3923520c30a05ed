// Internal: draws from the factor posterior N(mean, blockdiag(P_k)) and empirical quantiles, shared by the
// interval methods (uncertainty.cpp) and the bounded answers (bounded_answer.cpp) so both sample alike.
#pragma once

#include "causal/analysis/structural_model.hpp"

#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

namespace causal::analysis::detail {

// Outcomes are filtered independently, so their factors are drawn independently; within an outcome the
// full block P_k is used. Fixed seed: the same posterior gives the same draws.
class PosteriorSampler {
 public:
  PosteriorSampler(const estimation::SvarLayout& layout, const FactorPosterior& posterior, std::uint64_t seed);
  // The next factor vector (layout order).
  const Eigen::VectorXd& next();

 private:
  const estimation::SvarLayout& layout_;
  const FactorPosterior& posterior_;
  std::vector<Eigen::MatrixXd> roots_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::VectorXd x_;
};

// Linear interpolation between order statistics at p (0..1) of a SORTED, non-empty sample.
double percentile(const std::vector<double>& sorted, double p);

}  // namespace causal::analysis::detail
