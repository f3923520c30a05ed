// causal-whatif: turn a channel table into an estimated structural model (the CLI's only modelling code).
//
// Steps: optional centering (subtract the calibration-window mean: the SVAR has no intercept, effects are
// differences and do not change), the instantaneous restriction (VAR-LiNGAM order, a configured graph, or
// none), noise (given q/r, or tuned per outcome by causal::estimation::tune_noise_all on the calibration window), then
// the Kalman filter over all rows: per-sample estimates (for counterfactuals) and the full posterior at one
// sample (for what-if and recommendations).
#pragma once

#include <causal/analysis/structural_model.hpp>
#include <causal/analysis/var_lingam.hpp>
#include <causal/estimation/batch_estimation.hpp>
#include <causal/io/channel_csv.hpp>
#include <causal/estimation/noise_params.hpp>
#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace causal::whatif {

enum class OrderSource { none, lingam, graph };

struct ModelOptions {
  int lag_order = 1;
  bool self_lags = false;
  OrderSource order_source = OrderSource::none;
  std::string graph;          // for OrderSource::graph: "1->2, 2->3" (names or 1-based indices)
  int calibration_rows = 0;   // first rows used for centering, VAR-LiNGAM and noise tuning; 0 = all rows
  bool center = true;
  std::optional<double> q;    // both absent: tuned
  std::optional<double> r;
  double p0 = 1.0;
  int at = -1;                // sample (0-based) of the model snapshot; -1 = last row
};

struct FittedModel {
  std::vector<std::string> names;
  Eigen::MatrixXd raw;                    // N x G as read
  Eigen::VectorXd center;                 // subtracted per channel (zeros without centering)
  Eigen::MatrixXd centered;               // N x G data the model was fitted to
  estimation::ModelSpec spec;
  std::optional<estimation::SvarLayout> layout;
  std::vector<estimation::NoiseParams> noise;
  bool noise_tuned = false;
  std::optional<analysis::VarLingamResult> lingam;
  std::vector<int> order;                 // instantaneous causal order when restricted (empty otherwise)
  estimation::EstimationRun run;                      // per-sample filtered estimates
  analysis::FactorPosterior posterior;    // at sample `at`
  int at = 0;
  analysis::DynamicsCheck dynamics;       // of the snapshot model
  int calibration_rows = 0;
};

// Throws std::invalid_argument with a clear message for unusable options or data (too few rows, a
// cyclic graph, a constant channel in the calibration window, ...).
FittedModel fit_model(const io::ChannelTable& table, const ModelOptions& options);

// A channel given as a name (exact) or a 1-based index -> 0-based. Throws std::invalid_argument.
int resolve_channel(const std::string& token, const std::vector<std::string>& names);

}  // namespace causal::whatif
