#include "alarm_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "causal/alarms/statistics.hpp"
#include "causal/io/condition_features.hpp"
#include "causal/io/feature_table.hpp"
#include "causal/io/ims_directory.hpp"
#include "causal/noise_tuning.hpp"
#include "causal/svar_kalman_filter.hpp"
#include "causal/svar_layout.hpp"

namespace causal::alarm_eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

causal::io::ConditionFeature feature_or_throw(const std::string& feature) {
  const auto f = causal::io::parse_condition_feature(feature);
  if (!f) throw std::invalid_argument("unknown condition feature '" + feature + "' (rms, meanabs, kurtosis, peak)");
  return *f;
}

}  // namespace

ConditionSeries series_from_feature_table(const std::string& path, const std::string& feature) {
  const std::string suffix = feature.empty() ? "" : causal::io::derived_column_suffix(feature_or_throw(feature));
  const auto table = causal::io::read_feature_table(path, suffix);
  ConditionSeries s;
  s.channel_names = table.channel_names;
  s.time_ns = table.time_ns;
  s.values = table.values;
  s.feature = feature.empty() ? "meanabs" : causal::io::to_string(feature_or_throw(feature));
  const std::size_t n = table.time_ns.size();
  s.index.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.index[i] = i;
  // A time gap larger than 2.5 x the median interval restarts the condition-level lags.
  s.discontinuity.assign(n, false);
  std::vector<double> dt;
  for (std::size_t i = 1; i < n; ++i) dt.push_back(static_cast<double>(s.time_ns[i] - s.time_ns[i - 1]));
  const double med = dt.empty() ? 0.0 : causal::alarms::median(dt);
  for (std::size_t i = 0; i < n; ++i) s.discontinuity[i] = i == 0 || dt[i - 1] > 2.5 * med;
  return s;
}

ConditionSeries series_from_ims_directory(const std::string& dir, const std::string& feature, bool verbose_progress) {
  const auto f = feature_or_throw(feature);
  const auto listing = causal::io::list_ims_directory(dir);
  const auto& snaps = listing.snapshots;
  ConditionSeries s;
  s.feature = causal::io::to_string(f);
  const std::size_t n = snaps.size();
  s.time_ns.resize(n);
  s.index.resize(n);
  s.discontinuity.assign(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::MatrixXd x = causal::io::read_ims_snapshot(snaps[i].path);
    if (i == 0) {
      s.values.resize(static_cast<Eigen::Index>(n), x.cols());
      for (Eigen::Index g = 0; g < x.cols(); ++g) s.channel_names.push_back("bearing" + std::to_string(g + 1));
    }
    if (x.cols() != s.values.cols()) throw std::runtime_error(snaps[i].path + ": channel count changed");
    s.values.row(static_cast<Eigen::Index>(i)) = causal::io::compute_condition_feature(x, f).transpose();
    s.time_ns[i] = snaps[i].time_ns;
    if (verbose_progress && (i % 50 == 0 || i + 1 == n)) std::fprintf(stderr, "  read %zu / %zu snapshots\n", i + 1, n);
  }
  // Run index from time: period = smallest interval; discontinuity where a gap exceeds 2.5 x the median.
  std::vector<std::int64_t> dt;
  for (std::size_t i = 1; i < n; ++i) dt.push_back(s.time_ns[i] - s.time_ns[i - 1]);
  const std::int64_t period = dt.empty() ? 1 : *std::min_element(dt.begin(), dt.end());
  std::vector<double> dtd(dt.begin(), dt.end());
  const double med = dt.empty() ? 0.0 : causal::alarms::median(dtd);
  for (std::size_t i = 0; i < n; ++i) {
    s.index[i] = static_cast<std::uint64_t>(std::llround(static_cast<double>(s.time_ns[i] - s.time_ns[0]) / static_cast<double>(period)));
    s.discontinuity[i] = i == 0 || static_cast<double>(dt[i - 1]) > 2.5 * med;
  }
  return s;
}

PipelineResult run_condition_pipeline(const ConditionSeries& series, const PipelineOptions& options) {
  using namespace causal::alarms;
  const auto n = series.values.rows();
  const auto g = series.values.cols();
  const auto& p = options.params;
  p.validate();
  if (g < 2) throw std::invalid_argument("the condition pipeline needs at least 2 channels");
  const Eigen::Index base_begin = std::min<Eigen::Index>(n, p.warmup_observations);
  const Eigen::Index base_end = std::min<Eigen::Index>(n, p.warmup_observations + p.baseline_observations);
  if (base_end - base_begin < 8) throw std::invalid_argument("series shorter than warm-up + baseline");

  PipelineResult res;
  // Filter input: log feature standardised by the baseline median / MAD of the same window the alarm engine
  // learns from. Centring makes the causal factors describe co-movements of the channels around their
  // healthy levels (the model has no intercept), and unit scale makes them dimensionless and comparable.
  Eigen::MatrixXd y(n, g);
  for (Eigen::Index c = 0; c < g; ++c) {
    std::vector<double> base;
    for (Eigen::Index t = base_begin; t < base_end; ++t) {
      const double v = series.values(t, c);
      base.push_back(v > 0.0 ? std::log(v) : kNaN);
    }
    const RobustStats st = robust_stats(base);
    res.baseline_median_log.push_back(st.location);
    res.baseline_scale_log.push_back(st.scale);
    for (Eigen::Index t = 0; t < n; ++t) {
      const double v = series.values(t, c);
      const double z = v > 0.0 && std::isfinite(v) ? (std::log(v) - st.location) / st.scale : kNaN;
      y(t, c) = options.standardize_input ? z : z * st.scale + st.location;
    }
  }

  causal::ModelSpec spec;
  spec.channels = static_cast<int>(g);
  spec.lag_order = options.lag_order;
  spec.include_self_lags = options.include_self_lags;
  const causal::SvarLayout layout(spec);
  std::vector<bool> disc(series.discontinuity.begin(), series.discontinuity.end());
  disc.resize(static_cast<std::size_t>(n), false);

  res.noise.assign(static_cast<std::size_t>(g), options.noise);
  res.tuning_messages.assign(static_cast<std::size_t>(g), "");
  if (options.tune_noise) {
    const Eigen::MatrixXd window = y.middleRows(base_begin, base_end - base_begin);
    std::vector<bool> wdisc(disc.begin() + base_begin, disc.begin() + base_end);
    wdisc[0] = true;
    causal::NoiseTuningOptions topt;
    topt.p0 = options.noise.p0;
    for (int k = 0; k < spec.channels; ++k) {
      const auto tr = causal::tune_noise(layout, k, window, wdisc, topt);
      res.noise[static_cast<std::size_t>(k)] = tr.noise;
      res.tuning_messages[static_cast<std::size_t>(k)] = tr.message;
    }
  }

  causal::SvarKalmanFilter filter(layout, res.noise);
  AlarmEngine engine(options.asset_group, series.channel_names, layout.factor_names(), p);
  res.cusum_threshold = engine.cusum_threshold();
  res.nis_threshold = engine.nis_threshold();
  res.feature_z = Eigen::MatrixXd::Constant(n, g, kNaN);
  res.innovation_z = Eigen::MatrixXd::Constant(n, g, kNaN);
  const int total = layout.total_factors();
  std::vector<double> x(static_cast<std::size_t>(total)), sd(static_cast<std::size_t>(total));
  res.summary.resize(static_cast<std::size_t>(g));
  for (Eigen::Index c = 0; c < g; ++c) res.summary[static_cast<std::size_t>(c)].name = series.channel_names[static_cast<std::size_t>(c)];
  std::vector<bool> first_active(static_cast<std::size_t>(g), false);

  // The engine's operating-state gate, applied to the filter input as well: a snapshot in which every
  // channel is far below its baseline (machine stopped) is not fed to the filter (NaN row: rejected,
  // counted, lags restart), so it cannot drag the causal factors.
  const double stopped_log = p.stopped_ratio > 0.0 ? std::log(p.stopped_ratio) : -std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < n; ++t) {
    Eigen::VectorXd row = y.row(t).transpose();
    bool stopped = p.feature_log_transform && p.stopped_ratio > 0.0;
    for (Eigen::Index c = 0; c < g && stopped; ++c) {
      const auto ci = static_cast<std::size_t>(c);
      const double dev = options.standardize_input ? row(c) * res.baseline_scale_log[ci] : row(c) - res.baseline_median_log[ci];
      stopped = std::isfinite(dev) && dev < stopped_log;
    }
    if (stopped) {
      row.setConstant(kNaN);
      ++res.not_running;
    }
    const auto status = filter.step(row.data(), disc[static_cast<std::size_t>(t)]);
    Observation o;
    o.index = series.index[static_cast<std::size_t>(t)];
    o.time_ns = series.time_ns[static_cast<std::size_t>(t)];
    o.discontinuity = t > 0 && disc[static_cast<std::size_t>(t)];
    o.features = series.values.row(t).transpose();
    o.innovations = Eigen::VectorXd::Constant(g, kNaN);
    o.innovation_variances = Eigen::VectorXd::Constant(g, kNaN);
    if (status == causal::SampleStatus::Updated) {
      ++res.filter_updates;
      for (int k = 0; k < spec.channels; ++k) {
        o.innovations(k) = filter.last_innovation(k);
        o.innovation_variances(k) = filter.last_innovation_variance(k);
      }
    }
    filter.estimates(x.data());
    filter.std_devs(sd.data());
    o.factors = Eigen::Map<const Eigen::VectorXd>(x.data(), total);
    o.factor_std = Eigen::Map<const Eigen::VectorXd>(sd.data(), total);
    if (options.on_observation) options.on_observation(o);
    auto events = engine.observe(o);
    for (Eigen::Index c = 0; c < g; ++c) {
      const auto d = engine.channel_diagnostics(static_cast<int>(c));
      res.feature_z(t, c) = d.feature.last_z;
      res.innovation_z(t, c) = d.innovation.last_z;
    }
    for (auto& e : events) {
      if (e.category != category::kDegradation) {  // operating changes are reported, not faults
        ++res.operating_changes;
        res.events.push_back(std::move(e));
        continue;
      }
      auto& s = res.summary[static_cast<std::size_t>(e.channel)];
      const auto ci = static_cast<std::size_t>(e.channel);
      if (e.state == AlarmState::Raised && !s.alarmed) {
        s.alarmed = true;
        s.first = e;
        first_active[ci] = true;
      }
      if (first_active[ci] && e.alarm_id == s.first.alarm_id && e.state == AlarmState::Cleared) {
        first_active[ci] = false;
        s.first_cleared_index = e.index;
      }
      if (e.state == AlarmState::Raised && e.kind == kind::kFeatureDrift && !s.feature_alarmed) {
        s.feature_alarmed = true;
        s.first_feature = e;
      }
      if (e.state != AlarmState::Cleared && static_cast<int>(e.severity) > static_cast<int>(s.max_severity)) {
        s.max_severity = e.severity;
        s.max_severity_index = e.index;
      }
      if (e.state != AlarmState::Cleared && s.max_severity_index == 0 && s.alarmed) s.max_severity_index = e.index;
      res.events.push_back(std::move(e));
    }
  }
  for (Eigen::Index c = 0; c < g; ++c) res.diagnostics.push_back(engine.channel_diagnostics(static_cast<int>(c)));
  for (auto& s : res.summary) {
    s.first_sustained = s.alarmed && (s.first_cleared_index == 0 ||
                                      s.first_cleared_index >= s.first.index + static_cast<std::uint64_t>(options.sustained_observations));
  }
  return res;
}

}  // namespace causal::alarm_eval
