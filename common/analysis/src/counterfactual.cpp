#include "causal/analysis/counterfactual.hpp"

#include "linear_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::analysis {
namespace {

void check_query(const Eigen::MatrixXd& data, const CounterfactualQuery& query, int channels, int lag_order) {
  if (data.cols() != channels) {
    throw std::invalid_argument("counterfactual: data has " + std::to_string(data.cols()) + " channels, model " +
                                std::to_string(channels));
  }
  if (query.from > query.to || query.from < 0 || query.to >= data.rows()) {
    throw std::invalid_argument("counterfactual: window [" + std::to_string(query.from) + ", " +
                                std::to_string(query.to) + "] is not inside the data (0.." +
                                std::to_string(data.rows() - 1) + ")");
  }
  if (query.from < lag_order) {
    throw std::invalid_argument("counterfactual: window must start at sample >= " + std::to_string(lag_order) +
                                " (needs lag_order samples of history)");
  }
  std::vector<bool> held(static_cast<std::size_t>(channels), false);
  for (const Hold& h : query.holds) {
    if (h.channel < 0 || h.channel >= channels) {
      throw std::invalid_argument("counterfactual: hold channel " + std::to_string(h.channel) + " outside 0.." +
                                  std::to_string(channels - 1));
    }
    if (held[h.channel]) throw std::invalid_argument("counterfactual: channel " + std::to_string(h.channel) + " held twice");
    held[h.channel] = true;
  }
}

template <typename ModelAt>
CounterfactualResult run(const ModelAt& model_at, int channels, int lag_order, const Eigen::MatrixXd& data,
                         const CounterfactualQuery& query) {
  check_query(data, query, channels, lag_order);
  const int rows = query.to - query.from + 1;
  CounterfactualResult result;
  result.from = query.from;
  result.to = query.to;
  result.observed = data.middleRows(query.from, rows);
  result.counterfactual = Eigen::MatrixXd::Constant(rows, channels, std::numeric_limits<double>::quiet_NaN());
  result.noise = result.counterfactual;
  if (!data.middleRows(query.from - lag_order, rows + lag_order).allFinite()) {
    result.status = AnalysisStatus::non_finite_input;
    result.message = "non-finite data in the window or its lag_order samples of history";
    return result;
  }
  std::vector<int> held_channels;
  for (const Hold& h : query.holds) {
    if (!std::isfinite(h.value)) {
      result.status = AnalysisStatus::non_finite_input;
      result.message = "non-finite hold value";
      return result;
    }
    held_channels.push_back(h.channel);
  }

  // Prediction in deviation form d[n] = y*[n] - y[n] (d = 0 before `from`). Substituting (C1) into (C2),
  // the noise cancels row by row:
  //   non-held k:  row_k(I - A0) d[n] = sum_l row_k(A_l) d[n-l]                              (C2')
  //   held j:      d_j[n] = c_j - y_j[n]
  // i.e. (I - A0c) d[n] = sum_l A_lc d[n-l] + f[n]. Same result as (C2) in exact arithmetic, but without a
  // hold d stays exactly 0, so the data are reproduced bit for bit even when the model is unstable (where
  // re-simulating y* directly would amplify rounding exponentially).
  Eigen::MatrixXd dev = Eigen::MatrixXd::Zero(rows + lag_order, channels);  // row lag_order + i <-> sample from + i
  for (int i = 0; i < rows; ++i) {
    const int n = query.from + i;
    const StructuralModel& model = model_at(i);
    if (!all_finite(model)) {
      result.status = AnalysisStatus::non_finite_input;
      result.message = "non-finite model coefficients at sample " + std::to_string(n);
      result.counterfactual.setConstant(std::numeric_limits<double>::quiet_NaN());
      return result;
    }
    // (C1) abduction from the observed data (reported; the prediction uses it implicitly through (C2')).
    Eigen::VectorXd e = data.row(n).transpose() - model.a0 * data.row(n).transpose();
    for (int l = 1; l <= lag_order; ++l) e.noalias() -= model.lags[static_cast<std::size_t>(l - 1)] * data.row(n - l).transpose();
    result.noise.row(i) = e.transpose();

    const StructuralModel cut = graph_surgery(model, held_channels);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(channels);
    for (int l = 1; l <= lag_order; ++l) {
      rhs.noalias() += cut.lags[static_cast<std::size_t>(l - 1)] * dev.row(lag_order + i - l).transpose();
    }
    for (const Hold& h : query.holds) rhs(h.channel) = h.value - data(n, h.channel);
    const detail::InstantaneousSolve solve(cut.a0);
    if (!solve.ok()) {
      result.status = AnalysisStatus::not_identifiable;
      result.message = "(I - A0) with the held channels cut is singular at sample " + std::to_string(n) +
                       ": the instantaneous equations have no unique solution";
      result.counterfactual.setConstant(std::numeric_limits<double>::quiet_NaN());
      return result;
    }
    if (!held_channels.empty()) {
      const double rho = check_dynamics(cut).spectral_radius;
      result.spectral_radius = std::isnan(rho) ? rho : std::max(result.spectral_radius, rho);
    }
    const Eigen::VectorXd d = held_channels.empty() ? Eigen::VectorXd(Eigen::VectorXd::Zero(channels)) : Eigen::VectorXd(solve.solve(rhs));
    dev.row(lag_order + i) = d.transpose();
    Eigen::VectorXd y = data.row(n).transpose() + d;
    for (const Hold& h : query.holds) y(h.channel) = h.value;  // exact, not to rounding
    result.counterfactual.row(i) = y.transpose();
  }
  return result;
}

}  // namespace

CounterfactualResult counterfactual(const StructuralModel& model, const Eigen::MatrixXd& data,
                                    const CounterfactualQuery& query) {
  validate_model(model);
  return run([&](int) -> const StructuralModel& { return model; }, model.channels(), model.lag_order(), data, query);
}

CounterfactualResult counterfactual(const std::vector<StructuralModel>& models, const Eigen::MatrixXd& data,
                                    const CounterfactualQuery& query) {
  if (models.empty()) throw std::invalid_argument("counterfactual: no models");
  if (static_cast<long>(models.size()) != static_cast<long>(query.to) - query.from + 1) {
    throw std::invalid_argument("counterfactual: " + std::to_string(models.size()) +
                                " models for a window of " + std::to_string(query.to - query.from + 1) + " samples");
  }
  for (const auto& m : models) {
    validate_model(m);
    if (m.channels() != models.front().channels() || m.lag_order() != models.front().lag_order()) {
      throw std::invalid_argument("counterfactual: models disagree on channels or lag order");
    }
  }
  return run([&](int i) -> const StructuralModel& { return models[static_cast<std::size_t>(i)]; },
             models.front().channels(), models.front().lag_order(), data, query);
}

}  // namespace causal::analysis
