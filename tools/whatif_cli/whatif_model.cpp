#include "whatif_model.hpp"

#include <causal/analysis/causal_graph.hpp>
#include <causal/estimation/noise_tuning.hpp>
#include <causal/estimation/svar_kalman_filter.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace causal::whatif {
namespace {

// Mean of the finite values of each column over the first `rows` rows.
Eigen::VectorXd finite_column_means(const Eigen::MatrixXd& values, int rows) {
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(values.cols());
  for (Eigen::Index c = 0; c < values.cols(); ++c) {
    double sum = 0.0;
    long count = 0;
    for (int r = 0; r < rows; ++r) {
      if (std::isfinite(values(r, c))) {
        sum += values(r, c);
        ++count;
      }
    }
    if (count == 0) throw std::invalid_argument("channel " + std::to_string(c + 1) + " has no finite value in the calibration window");
    mean(c) = sum / static_cast<double>(count);
  }
  return mean;
}

}  // namespace

int resolve_channel(const std::string& token, const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == token) return static_cast<int>(i);
  const bool numeric = !token.empty() && token.size() < 9 &&
                       std::all_of(token.begin(), token.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
  if (numeric) {
    const int one_based = std::stoi(token);
    if (one_based >= 1 && one_based <= static_cast<int>(names.size())) return one_based - 1;
  }
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) list += (i ? ", " : "") + std::to_string(i + 1) + "=" + names[i];
  throw std::invalid_argument("unknown channel '" + token + "' (give a name or a 1-based index: " + list + ")");
}

FittedModel fit_model(const io::ChannelTable& table, const ModelOptions& options) {
  FittedModel fm;
  fm.names = table.channel_names;
  const int g = static_cast<int>(table.values.cols());
  const int n = static_cast<int>(table.values.rows());
  if (g < 2) throw std::invalid_argument("need at least 2 channels, the file has " + std::to_string(g));
  if (options.lag_order < 1) throw std::invalid_argument("--lag-order must be >= 1");
  const int min_rows = 10 * (g * (options.lag_order + 1)) + options.lag_order;
  if (n < min_rows) {
    throw std::invalid_argument("the file has " + std::to_string(n) + " rows; need at least " + std::to_string(min_rows) +
                                " for " + std::to_string(g) + " channels and lag order " + std::to_string(options.lag_order));
  }
  fm.calibration_rows = options.calibration_rows == 0 ? n : options.calibration_rows;
  if (fm.calibration_rows < min_rows || fm.calibration_rows > n) {
    throw std::invalid_argument("--calibration must be between " + std::to_string(min_rows) + " and the row count " +
                                std::to_string(n));
  }
  fm.at = options.at < 0 ? n - 1 : options.at;
  if (fm.at < options.lag_order || fm.at >= n) {
    throw std::invalid_argument("--at must be a row index in " + std::to_string(options.lag_order) + ".." + std::to_string(n - 1));
  }

  fm.center = options.center ? finite_column_means(table.values, fm.calibration_rows) : Eigen::VectorXd::Zero(g);
  fm.raw = table.values;
  fm.centered = table.values.rowwise() - fm.center.transpose();

  fm.spec.channels = g;
  fm.spec.lag_order = options.lag_order;
  fm.spec.include_self_lags = options.self_lags;
  switch (options.order_source) {
    case OrderSource::none:
      break;
    case OrderSource::lingam: {
      analysis::VarLingamOptions lo;
      lo.lag_order = options.lag_order;
      lo.intercept = true;
      fm.lingam = analysis::var_lingam(fm.centered.topRows(fm.calibration_rows), lo);  // the VAR fit skips
                                                                                          // rows with NaN
      fm.order = fm.lingam->order;
      fm.spec = fm.lingam->restrict(fm.spec);
      break;
    }
    case OrderSource::graph: {
      const analysis::CausalGraph graph = analysis::parse_causal_graph(options.graph, g, fm.names);
      const std::vector<int> cycle = graph.find_cycle();
      if (!cycle.empty()) {
        throw std::invalid_argument("--graph has an instantaneous cycle: " + analysis::describe_cycle(cycle, fm.names) +
                                    "; instantaneous links must be acyclic");
      }
      fm.spec = graph.apply_to(fm.spec);
      fm.order = graph.topological_order();
      break;
    }
  }
  fm.layout.emplace(fm.spec);

  if (options.q || options.r) {
    estimation::NoiseParams np;
    if (options.q) np.q = *options.q;
    if (options.r) np.r = *options.r;
    np.p0 = options.p0;
    estimation::validate_noise_params(np, "--q/--r/--p0");
    fm.noise.assign(static_cast<std::size_t>(g), np);
  } else {
    estimation::NoiseTuningOptions to;
    to.p0 = options.p0;
    for (const estimation::NoiseTuningResult& t : estimation::tune_noise_all(*fm.layout, fm.centered.topRows(fm.calibration_rows), {}, to)) {
      fm.noise.push_back(t.noise);
    }
    fm.noise_tuned = true;
  }

  fm.run = estimation::run_filter(*fm.layout, fm.noise, fm.centered);
  // Full covariance blocks at `at`: step a filter to that sample (run_filter keeps only std devs).
  estimation::SvarKalmanFilter filter(*fm.layout, fm.noise);
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = fm.centered.topRows(fm.at + 1);
  for (int t = 0; t <= fm.at; ++t) filter.step(rows.row(t).data());
  fm.posterior = analysis::posterior_from_filter(*fm.layout, filter);
  fm.dynamics = analysis::check_dynamics(analysis::assemble_structural_model(*fm.layout, fm.posterior.mean));
  return fm;
}

}  // namespace causal::whatif
