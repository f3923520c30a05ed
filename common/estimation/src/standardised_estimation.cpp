#include "causal/estimation/standardised_estimation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "causal/io/enum_names.hpp"

namespace causal::estimation {
namespace {

constexpr double kMadToSigma = 0.6744897501960817;  // median |N(0, 1)|
// Spread below this share of the channel's level is rounding, not signal (doubles carry ~16 digits).
constexpr double kConstantRelative = 1e-12;
// Scales beyond these make z = y / s overflow or lose all precision (subnormal): refused, not guessed.
constexpr double kMinScale = 1e-280;
constexpr double kMaxScale = 1e280;

std::string channel_label(int j, const std::vector<std::string>& names) {
  std::string s = "channel " + std::to_string(j + 1);
  if (j >= 0 && j < static_cast<int>(names.size())) s += " '" + names[j] + "'";
  return s;
}

// Factor column c -> (outcome, regressor) of the layout.
struct FactorRef {
  int outcome = -1;
  Regressor regressor{-1, 0};
};

std::vector<FactorRef> factor_refs(const SvarLayout& layout) {
  std::vector<FactorRef> refs(layout.total_factors());
  for (int k = 0; k < layout.channels(); ++k) {
    const auto& regs = layout.regressors(k);
    for (int i = 0; i < layout.factor_count(k); ++i) refs[layout.offset(k) + i] = {k, regs[i]};
  }
  return refs;
}

}  // namespace

const char* to_string(ScaleStatus status) {
  static constexpr auto kNames = io::enum_names<ScaleStatus>({{ScaleStatus::Ok, "ok"},
                                                              {ScaleStatus::ConstantChannel, "constant"},
                                                              {ScaleStatus::NoFiniteValues, "no finite values"},
                                                              {ScaleStatus::OutOfRange, "scale out of range"}});
  return kNames.name(status, "unknown");
}

const char* to_string(EstimationStatus status) {
  static constexpr auto kNames =
      io::enum_names<EstimationStatus>({{EstimationStatus::Ok, "ok"},
                                        {EstimationStatus::ConstantChannel, "constant channel"},
                                        {EstimationStatus::UnusableChannel, "unusable channel"},
                                        {EstimationStatus::TuningFailed, "noise tuning failed"},
                                        {EstimationStatus::NonFiniteOutput, "non-finite output"}});
  return kNames.name(status, "unknown");
}

bool ChannelScales::ok() const { return first_refused() < 0; }

int ChannelScales::first_refused() const {
  for (std::size_t j = 0; j < status.size(); ++j) {
    if (status[j] != ScaleStatus::Ok) return static_cast<int>(j);
  }
  return -1;
}

ChannelScales robust_channel_scales(const Eigen::MatrixXd& window) {
  const auto g = static_cast<int>(window.cols());
  ChannelScales out;
  out.scale.assign(g, 1.0);
  out.status.assign(g, ScaleStatus::Ok);
  std::vector<double> values;
  for (int j = 0; j < g; ++j) {
    values.clear();
    for (Eigen::Index i = 0; i < window.rows(); ++i) {
      if (std::isfinite(window(i, j))) values.push_back(window(i, j));
    }
    if (values.empty()) {
      out.status[j] = ScaleStatus::NoFiniteValues;
      continue;
    }
    // Moments of y / peak, so that a channel near the top of the double range (1e160) cannot overflow its
    // own variance: the spread test and the scale are invariant to that division.
    double peak = 0.0;
    for (double v : values) peak = std::max(peak, std::abs(v));
    const auto n = static_cast<double>(values.size());
    const double inv_peak = peak > 0.0 ? 1.0 / peak : 1.0;
    double sum = 0.0, sum_abs = 0.0;
    for (double v : values) {
      sum += v * inv_peak;
      sum_abs += std::abs(v) * inv_peak;
    }
    const double mean = sum / n, mean_abs = sum_abs / n;
    double ss = 0.0, sq = 0.0;
    for (double v : values) {
      const double u = v * inv_peak;
      ss += (u - mean) * (u - mean);
      sq += u * u;
    }
    const double sd = std::sqrt(ss / n);
    if (!std::isfinite(sd) || !std::isfinite(mean_abs) || !std::isfinite(inv_peak)) {
      out.status[j] = ScaleStatus::OutOfRange;
      continue;
    }
    if (!(sd > kConstantRelative * mean_abs)) {  // also all zeros: 0 > 0 is false
      out.status[j] = ScaleStatus::ConstantChannel;
      continue;
    }
    for (double& v : values) v = std::abs(v);
    auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    double s = *mid / kMadToSigma;
    if (!(s > 0.0)) s = std::sqrt(sq / n) * peak;  // mostly zeros: the root mean square still sees the rest
    if (!(s > kMinScale && s < kMaxScale)) {
      out.status[j] = ScaleStatus::OutOfRange;
      continue;
    }
    out.scale[j] = s;
  }
  return out;
}

void to_user_units(const SvarLayout& layout, const std::vector<double>& scale, EstimationRun& run) {
  if (static_cast<int>(scale.size()) != layout.channels()) {
    throw std::invalid_argument("to_user_units: need one scale per channel");
  }
  const std::vector<FactorRef> refs = factor_refs(layout);
  for (Eigen::Index c = 0; c < run.estimates.cols(); ++c) {
    const double f = scale[refs[c].outcome] / scale[refs[c].regressor.channel];
    run.estimates.col(c) *= f;
    run.std_devs.col(c) *= f;
  }
  for (Eigen::Index k = 0; k < run.innovations.cols(); ++k) {
    run.innovations.col(k) *= scale[k];
    run.innovation_variances.col(k) *= scale[k] * scale[k];
  }
}

StandardisedRun estimate_standardised(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                      const std::vector<bool>& discontinuity, const StandardisedOptions& options,
                                      const std::vector<std::string>& channel_names) {
  const int g = layout.channels();
  if (samples.cols() != g) {
    throw std::invalid_argument("samples must have one column per channel (" + std::to_string(g) + "), got " +
                                std::to_string(samples.cols()));
  }
  if (!discontinuity.empty() && static_cast<Eigen::Index>(discontinuity.size()) != samples.rows()) {
    throw std::invalid_argument("discontinuity must be empty or have one flag per sample");
  }
  if (options.calibration_samples < 0 || options.lag < 0) {
    throw std::invalid_argument("StandardisedOptions: calibration_samples and lag must be >= 0");
  }
  StandardisedRun out;
  const Eigen::Index cal = options.calibration_samples > 0
                               ? std::min<Eigen::Index>(options.calibration_samples, samples.rows())
                               : samples.rows();
  out.scales = robust_channel_scales(samples.topRows(cal));
  if (const int j = out.scales.first_refused(); j >= 0) {
    const ScaleStatus s = out.scales.status[j];
    out.status = s == ScaleStatus::ConstantChannel ? EstimationStatus::ConstantChannel
                                                   : EstimationStatus::UnusableChannel;
    out.channel = j;
    std::ostringstream os;
    os << channel_label(j, channel_names) << " is ";
    if (s == ScaleStatus::ConstantChannel) {
      os << "constant over the " << cal << " calibration rows (dead or stuck sensor?): its factors cannot be "
         << "estimated; remove the channel or fix its data";
    } else if (s == ScaleStatus::NoFiniteValues) {
      os << "without one finite value in the " << cal << " calibration rows";
    } else {
      os << "at a magnitude double precision cannot standardise (robust scale outside [1e-280, 1e280])";
    }
    out.message = os.str();
    return out;
  }
  if (!options.standardise) std::fill(out.scales.scale.begin(), out.scales.scale.end(), 1.0);

  Eigen::MatrixXd z = samples;
  for (int j = 0; j < g; ++j) z.col(j) /= out.scales.scale[j];

  if (options.auto_noise) {
    const std::vector<bool> cal_disc =
        discontinuity.empty() ? std::vector<bool>{} : std::vector<bool>(discontinuity.begin(), discontinuity.begin() + cal);
    out.tuning = tune_noise_all(layout, z.topRows(cal), cal_disc, options.tuning);
    for (int k = 0; k < g; ++k) {
      const NoiseTuningResult& t = out.tuning[k];
      if (!t.usable) {
        out.status = EstimationStatus::TuningFailed;
        out.channel = k;
        out.message = channel_label(k, channel_names) + ": automatic noise failed: " + t.message;
        return out;
      }
      out.noise.push_back(t.noise);
    }
  } else {
    out.noise.assign(g, options.noise);
  }

  EstimationRun run;
  switch (options.estimator) {
    case EstimatorKind::Filter: run = run_filter(layout, out.noise, z, discontinuity, options.output); break;
    case EstimatorKind::FixedLag:
      run = run_fixed_lag_smoother(layout, out.noise, z, discontinuity, options.lag, options.output);
      break;
    case EstimatorKind::Rts: run = run_rts_smoother(layout, out.noise, z, discontinuity, options.output); break;
  }
  to_user_units(layout, out.scales.scale, run);

  // No output row may be silently NaN: find the earliest non-finite estimate or standard deviation.
  const std::vector<FactorRef> refs = factor_refs(layout);
  const std::vector<std::string> names = layout.factor_names();
  Eigen::Index bad_row = -1;
  Eigen::Index bad_col = -1;
  for (Eigen::Index c = 0; c < run.estimates.cols(); ++c) {
    const Eigen::Index limit = bad_row < 0 ? run.estimates.rows() : bad_row;
    for (Eigen::Index i = 0; i < limit; ++i) {
      if (!std::isfinite(run.estimates(i, c)) || !std::isfinite(run.std_devs(i, c))) {
        bad_row = i;
        bad_col = c;
        break;
      }
    }
  }
  if (bad_row >= 0) {
    const FactorRef& ref = refs[bad_col];
    out.status = EstimationStatus::NonFiniteOutput;
    out.channel = ref.outcome;
    out.row = bad_row * options.output.every;
    out.factor = names[bad_col];
    out.message = "factor " + out.factor + " (outcome " + channel_label(ref.outcome, channel_names) +
                  ", regressor " + channel_label(ref.regressor.channel, channel_names) + ") is not finite at row " +
                  std::to_string(out.row) + " (0-based data row): the estimate lost all precision";
    return out;
  }
  out.run = std::move(run);
  return out;
}

}  // namespace causal::estimation
