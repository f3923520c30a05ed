#include "offline_run.hpp"

#include <cmath>
#include <fstream>
#include <ostream>
#include <string>

#include "causal/estimation/batch_estimation.hpp"
#include "causal/io/numeric_table.hpp"
#include "causal/estimation/kernel_dispatch.hpp"
#include "causal/estimation/noise_tuning.hpp"
#include "causal/estimation/standardised_estimation.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::offline {
namespace {

bool blank(const std::string& line) {
  for (char c : line) {
    if (c != ' ' && c != '\t' && c != '\r') return false;
  }
  return true;
}

const char* estimator_name(Estimator e) {
  switch (e) {
    case Estimator::Filter: return "filter";
    case Estimator::FixedLag: return "fixed-lag";
    case Estimator::Rts: return "rts";
  }
  return "?";
}

}  // namespace

std::size_t data_row_line(const std::string& path, long row) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return 0;
  std::string line;
  std::size_t number = 0;
  long rows_seen = -1;  // the header is row -1
  while (std::getline(in, line)) {
    ++number;
    if (blank(line)) continue;
    if (rows_seen == row) return number;
    ++rows_seen;
  }
  return 0;
}

void run_offline(const std::string& path, const causal::io::ChannelTable& table, const OfflineOptions& options,
                 std::ostream& out, std::ostream& log) {
  const Eigen::MatrixXd& y = table.values;
  const auto g = static_cast<int>(y.cols());
  if (g < 2) {
    throw BadInput(path + ": need at least 2 channel columns, found " + std::to_string(g));
  }
  // The estimator would reject non-finite samples and carry on, but in an offline file they are almost always
  // an export error: refuse them with the line to look at.
  for (Eigen::Index i = 0; i < y.rows(); ++i) {
    for (int j = 0; j < g; ++j) {
      if (!std::isfinite(y(i, j))) {
        throw BadInput(path + ":" + std::to_string(data_row_line(path, static_cast<long>(i))) +
                       ": non-finite value in column '" + table.channel_names[j] + "' (sample " +
                       std::to_string(i) + ")");
      }
    }
  }
  if (y.rows() <= options.lag_order) {
    throw BadInput(path + ": " + std::to_string(y.rows()) + " samples, need more than lag order " +
                   std::to_string(options.lag_order));
  }

  estimation::ModelSpec spec;
  spec.channels = g;
  spec.lag_order = options.lag_order;
  spec.include_self_lags = options.self_lags;
  const estimation::SvarLayout layout(spec);

  estimation::StandardisedOptions sopt;
  switch (options.estimator) {
    case Estimator::Filter: sopt.estimator = estimation::EstimatorKind::Filter; break;
    case Estimator::FixedLag: sopt.estimator = estimation::EstimatorKind::FixedLag; break;
    case Estimator::Rts: sopt.estimator = estimation::EstimatorKind::Rts; break;
  }
  sopt.lag = options.lag;
  sopt.standardise = options.standardise;
  sopt.noise = options.noise;
  sopt.auto_noise = options.auto_noise;
  sopt.calibration_samples = options.calibration_samples;
  sopt.tuning.p0 = options.noise.p0;
  sopt.output.every = options.every;
  sopt.output.innovations = false;  // not written: 2 G doubles per sample saved
  const estimation::StandardisedRun res = estimation::estimate_standardised(layout, y, {}, sopt, table.channel_names);
  switch (res.status) {
    case estimation::EstimationStatus::Ok: break;
    case estimation::EstimationStatus::NonFiniteOutput:
      throw EstimationFailed(path + ":" + std::to_string(data_row_line(path, static_cast<long>(res.row))) + ": " +
                             res.message + "; no factors written");
    default: throw BadInput(path + ": " + res.message);
  }
  if (options.standardise) {
    const Eigen::Index cal_rows = options.calibration_samples > 0
                                      ? std::min<Eigen::Index>(options.calibration_samples, y.rows())
                                      : y.rows();
    log << "scales (robust, first " << cal_rows << " rows; factors reported in the file's units):";
    for (int j = 0; j < g; ++j) log << " " << table.channel_names[j] << "=" << res.scales.scale[j];
    log << "\n";
  }
  for (const estimation::NoiseTuningResult& t : res.tuning) log << "auto-noise: " << t.message << "\n";
  const estimation::EstimationRun& run = res.run;
  log << "estimator " << estimator_name(options.estimator) << ": " << y.rows() << " samples, " << g
      << " channels, " << layout.total_factors() << " factors; updated " << run.counters.updated << ", warm-up "
      << run.counters.warm_up << "; kernels " << estimation::kernel_instruction_set() << "\n";
  if (run.clamped_variances > 0) {
    log << "warning: " << run.clamped_variances << " filtered variances were <= 0 from rounding and reported "
        << "as standard deviation 0: those factors lost precision\n";
  }

  // The factor columns are the run's column-major matrices themselves: the writers read them in place.
  const std::vector<std::string> names = layout.factor_names();
  causal::io::NumericTableView table_out;
  table_out.index_name = "n";
  table_out.index_step = options.every;
  table_out.rows = run.estimates.rows();
  for (Eigen::Index c = 0; c < layout.total_factors(); ++c) {
    table_out.columns.push_back({names[c], run.estimates.col(c).data()});
  }
  for (Eigen::Index c = 0; c < layout.total_factors(); ++c) {
    table_out.columns.push_back({"sd_" + names[c], run.std_devs.col(c).data()});
  }
  switch (options.format) {
    case OutputFormat::Csv: causal::io::write_numeric_csv(out, table_out, options.threads); break;
    case OutputFormat::Columns: causal::io::write_numeric_columns(out, table_out); break;
  }
}

}  // namespace causal::offline
