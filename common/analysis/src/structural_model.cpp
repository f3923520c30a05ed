#include "causal/analysis/structural_model.hpp"

#include "linear_system.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::analysis {
namespace {

void check_factor_count(const estimation::SvarLayout& layout, Eigen::Index size, const char* what) {
  if (size != layout.total_factors()) {
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(size) + " entries but the layout has " +
                                std::to_string(layout.total_factors()) + " factors");
  }
}

// Where a regressor of outcome k lives in (A0, A_1..A_M).
double& slot(StructuralModel& model, int k, const estimation::Regressor& r) {
  return r.lag == 0 ? model.a0(k, r.channel) : model.lags[static_cast<std::size_t>(r.lag - 1)](k, r.channel);
}

}  // namespace

StructuralModel zero_model(int channels, int lag_order) {
  if (channels < 1 || lag_order < 0) throw std::invalid_argument("zero_model: need channels >= 1, lag_order >= 0");
  StructuralModel model;
  model.a0 = Eigen::MatrixXd::Zero(channels, channels);
  model.lags.assign(static_cast<std::size_t>(lag_order), Eigen::MatrixXd::Zero(channels, channels));
  return model;
}

void validate_model(const StructuralModel& model) {
  const Eigen::Index g = model.a0.rows();
  if (g < 1 || model.a0.cols() != g) throw std::invalid_argument("structural model: A0 must be square and non-empty");
  for (std::size_t l = 0; l < model.lags.size(); ++l) {
    if (model.lags[l].rows() != g || model.lags[l].cols() != g) {
      throw std::invalid_argument("structural model: A_" + std::to_string(l + 1) + " is not " + std::to_string(g) +
                                  "x" + std::to_string(g));
    }
  }
  for (Eigen::Index k = 0; k < g; ++k) {
    if (model.a0(k, k) != 0.0) {
      throw std::invalid_argument("structural model: A0 diagonal must be zero (channel " + std::to_string(k) + ")");
    }
  }
}

bool all_finite(const StructuralModel& model) {
  if (!model.a0.allFinite()) return false;
  for (const auto& a : model.lags)
    if (!a.allFinite()) return false;
  return true;
}

StructuralModel assemble_structural_model(const estimation::SvarLayout& layout, const Eigen::VectorXd& factors) {
  check_factor_count(layout, factors.size(), "factor vector");
  StructuralModel model = zero_model(layout.channels(), layout.lag_order());
  for (int k = 0; k < layout.channels(); ++k) {
    const auto& regs = layout.regressors(k);
    const int base = layout.offset(k);
    for (std::size_t i = 0; i < regs.size(); ++i) {
      // A self-regressor at lag 0 would break the zero diagonal of (S1); the layout never emits one.
      if (regs[i].lag == 0 && regs[i].channel == k) {
        throw std::invalid_argument("layout has an instantaneous self-regressor for channel " + std::to_string(k));
      }
      slot(model, k, regs[i]) = factors(base + static_cast<int>(i));
    }
  }
  return model;
}

Eigen::VectorXd factors_from_model(const estimation::SvarLayout& layout, const StructuralModel& model) {
  validate_model(model);
  if (model.channels() != layout.channels() || model.lag_order() != layout.lag_order()) {
    throw std::invalid_argument("factors_from_model: model and layout disagree on channels or lag order");
  }
  StructuralModel copy = model;  // slot() wants a mutable reference; reading only
  Eigen::VectorXd factors(layout.total_factors());
  for (int k = 0; k < layout.channels(); ++k) {
    const auto& regs = layout.regressors(k);
    for (std::size_t i = 0; i < regs.size(); ++i) factors(layout.offset(k) + static_cast<int>(i)) = slot(copy, k, regs[i]);
  }
  return factors;
}

FactorPosterior posterior_from_filter(const estimation::SvarLayout& layout, const estimation::SvarKalmanFilter& filter) {
  FactorPosterior posterior;
  posterior.mean.resize(layout.total_factors());
  for (int k = 0; k < layout.channels(); ++k) {
    const Eigen::VectorXd xk = filter.estimate(k);
    if (xk.size() != layout.factor_count(k)) throw std::invalid_argument("filter and layout disagree on factor count");
    posterior.mean.segment(layout.offset(k), layout.factor_count(k)) = xk;
    posterior.blocks.push_back(filter.covariance(k));
  }
  validate_posterior(layout, posterior);
  return posterior;
}

FactorPosterior posterior_from_std_devs(const estimation::SvarLayout& layout, const Eigen::VectorXd& mean,
                                        const Eigen::VectorXd& std_devs) {
  check_factor_count(layout, mean.size(), "factor mean");
  check_factor_count(layout, std_devs.size(), "factor std devs");
  FactorPosterior posterior;
  posterior.mean = mean;
  for (int k = 0; k < layout.channels(); ++k) {
    const Eigen::VectorXd s = std_devs.segment(layout.offset(k), layout.factor_count(k));
    posterior.blocks.push_back(s.cwiseProduct(s).asDiagonal());
  }
  return posterior;
}

void validate_posterior(const estimation::SvarLayout& layout, const FactorPosterior& posterior) {
  check_factor_count(layout, posterior.mean.size(), "posterior mean");
  if (static_cast<int>(posterior.blocks.size()) != layout.channels()) {
    throw std::invalid_argument("posterior has " + std::to_string(posterior.blocks.size()) +
                                " covariance blocks, expected one per channel (" + std::to_string(layout.channels()) +
                                ")");
  }
  for (int k = 0; k < layout.channels(); ++k) {
    const auto& b = posterior.blocks[static_cast<std::size_t>(k)];
    if (b.rows() != layout.factor_count(k) || b.cols() != layout.factor_count(k)) {
      throw std::invalid_argument("posterior covariance block " + std::to_string(k) + " is not " +
                                  std::to_string(layout.factor_count(k)) + " square");
    }
  }
}

StructuralModel graph_surgery(const StructuralModel& model, const std::vector<int>& replaced) {
  validate_model(model);
  StructuralModel cut = model;
  for (int j : replaced) {
    if (j < 0 || j >= model.channels()) {
      throw std::invalid_argument("graph_surgery: channel " + std::to_string(j) + " outside 0.." +
                                  std::to_string(model.channels() - 1));
    }
    cut.a0.row(j).setZero();
    for (auto& a : cut.lags) a.row(j).setZero();
  }
  return cut;
}

Eigen::MatrixXd companion_matrix(const StructuralModel& model) {
  validate_model(model);
  detail::InstantaneousSolve solve(model.a0);
  if (!solve.ok()) throw std::invalid_argument("companion_matrix: (I - A0) is singular");
  return detail::companion_from(solve, model.lags);
}

DynamicsCheck check_dynamics(const StructuralModel& model) {
  validate_model(model);
  DynamicsCheck check;
  if (!all_finite(model)) {
    check.status = AnalysisStatus::non_finite_input;
    check.spectral_radius = std::numeric_limits<double>::quiet_NaN();
    check.message = "structural model has non-finite coefficients";
    return check;
  }
  detail::InstantaneousSolve solve(model.a0);
  check.rcond = solve.rcond();
  if (!solve.ok()) {
    check.status = AnalysisStatus::not_identifiable;
    check.spectral_radius = std::numeric_limits<double>::quiet_NaN();
    check.message = "(I - A0) is singular (rcond " + std::to_string(check.rcond) +
                    "): the instantaneous equations have no unique solution; restrict the instantaneous links to an "
                    "acyclic causal graph";
    return check;
  }
  check.spectral_radius = detail::spectral_radius(companion_matrix(model));
  if (!(check.spectral_radius < detail::kUnstableRadius)) {
    check.status = AnalysisStatus::unstable;
    check.message = "companion spectral radius " + std::to_string(check.spectral_radius) +
                    " >= 1: the system does not settle, there is no steady state";
  }
  return check;
}

}  // namespace causal::analysis
