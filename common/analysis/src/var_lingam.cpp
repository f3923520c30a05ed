#include "causal/analysis/var_lingam.hpp"

#include "causal/analysis/causal_graph.hpp"
#include "causal/analysis/direct_lingam.hpp"

#include <cmath>
#include <stdexcept>

namespace causal::analysis {

StructuralModel VarLingamResult::model() const {
  StructuralModel m;
  m.a0 = b0;
  m.lags = lagged;
  return m;
}

estimation::ModelSpec VarLingamResult::restrict(estimation::ModelSpec spec) const {
  const std::size_t g = instantaneous_allowed.size();
  if (spec.channels != static_cast<int>(g)) {
    throw std::invalid_argument("VAR-LiNGAM result has " + std::to_string(g) + " channels, model spec " +
                                std::to_string(spec.channels));
  }
  // Start from the order (intersects an existing mask), then apply pruning.
  spec = restrict_to_order(std::move(spec), order);
  for (std::size_t k = 0; k < g; ++k)
    for (std::size_t j = 0; j < g; ++j) spec.instantaneous_allowed[k][j] = spec.instantaneous_allowed[k][j] && instantaneous_allowed[k][j];
  return spec;
}

VarLingamResult var_lingam(const Eigen::MatrixXd& samples, const VarLingamOptions& options) {
  if (options.prune_threshold < 0.0 || !std::isfinite(options.prune_threshold)) {
    throw std::invalid_argument("VAR-LiNGAM: prune_threshold must be finite and >= 0");
  }
  VarLingamResult result;
  result.var = fit_var_least_squares(samples, options.lag_order, options.intercept);
  const DirectLingamResult lingam = direct_lingam(result.var.residuals);
  result.order = lingam.order;
  result.b0 = lingam.b0;
  const int g = static_cast<int>(samples.cols());
  const Eigen::MatrixXd i_minus_b0 = Eigen::MatrixXd::Identity(g, g) - result.b0;
  for (const auto& phi : result.var.coefficients) result.lagged.push_back(i_minus_b0 * phi);
  result.intercept = i_minus_b0 * result.var.intercept;
  const Eigen::MatrixXd& e = lingam.disturbances;
  result.noise_variance = e.colwise().squaredNorm().transpose() / static_cast<double>(e.rows());

  std::vector<int> position(static_cast<std::size_t>(g));
  for (int p = 0; p < g; ++p) position[result.order[p]] = p;
  result.instantaneous_allowed.assign(static_cast<std::size_t>(g), std::vector<bool>(static_cast<std::size_t>(g), false));
  for (int k = 0; k < g; ++k)
    for (int j = 0; j < g; ++j)
      result.instantaneous_allowed[k][j] =
          j != k && position[j] < position[k] && std::abs(result.b0(k, j)) >= options.prune_threshold;
  return result;
}

}  // namespace causal::analysis
