#include "causal/alarms/alarm_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "causal/alarms/condition_alarm_chain.hpp"
#include "causal/alarms/statistics.hpp"
#include "causal/pipeline/estimator_params.hpp"
#include "causal/io/condition_features.hpp"
#include "causal/io/feature_table.hpp"
#include "causal/io/ims_directory.hpp"

namespace causal::alarms {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

causal::io::ConditionFeature feature_or_throw(const std::string& feature) {
  const auto f = causal::io::parse_condition_feature(feature);
  if (!f) throw std::invalid_argument("unknown condition feature '" + feature + "' (rms, meanabs, kurtosis, peak)");
  return *f;
}

}  // namespace

ConditionSeries series_from_feature_table(const std::string& path, const std::string& feature, double gap_multiple) {
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
  // A time gap larger than gap_multiple x the median interval is a discontinuity (ConditionVector.discontinuity:
  // the estimator restarts its lags, the alarm engine re-baselines).
  s.discontinuity.assign(n, false);
  std::vector<double> dt;
  for (std::size_t i = 1; i < n; ++i) dt.push_back(static_cast<double>(s.time_ns[i] - s.time_ns[i - 1]));
  const double med = dt.empty() ? 0.0 : causal::alarms::median(dt);
  for (std::size_t i = 0; i < n; ++i) s.discontinuity[i] = i == 0 || dt[i - 1] > gap_multiple * med;
  return s;
}

ConditionSeries series_from_ims_directory(const std::string& dir, const std::string& feature, bool verbose_progress,
                                          double gap_multiple) {
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
  // Run index from time: period = smallest interval; discontinuity where a gap exceeds gap_multiple x the median.
  // A pause of the recording advances the index by one only: skipped indices are input that never arrived
  // (missing files; the alarm engine reports them as lost), a pause is a discontinuity of consecutive indices.
  std::vector<std::int64_t> dt;
  for (std::size_t i = 1; i < n; ++i) dt.push_back(s.time_ns[i] - s.time_ns[i - 1]);
  const std::int64_t period = dt.empty() ? 1 : *std::min_element(dt.begin(), dt.end());
  std::vector<double> dtd(dt.begin(), dt.end());
  const double med = dt.empty() ? 0.0 : causal::alarms::median(dtd);
  for (std::size_t i = 0; i < n; ++i) {
    s.discontinuity[i] = i == 0 || static_cast<double>(dt[i - 1]) > gap_multiple * med;
    const auto steps = i == 0 ? 0 : std::llround(static_cast<double>(dt[i - 1]) / static_cast<double>(period));
    s.index[i] = i == 0 ? 0 : s.index[i - 1] + (s.discontinuity[i] ? 1 : static_cast<std::uint64_t>(std::max(1LL, steps)));
  }
  return s;
}

causal::pipeline::AssetPipelineParams load_estimator_config(const std::string& path) {
  return causal::pipeline::load_estimator_params(path);
}

std::string shipped_estimator_config() { return std::string(CAUSAL_TWIN_ESTIMATOR_CONFIG); }

PipelineOptions shipped_options(const std::string& asset_group) {
  PipelineOptions o;
  o.asset_group = asset_group;
  o.estimator = load_estimator_config(shipped_estimator_config());
  return o;
}

PipelineResult run_condition_pipeline(const ConditionSeries& series, const PipelineOptions& options) {
  using namespace causal::alarms;
  const auto n = series.values.rows();
  const auto g = series.values.cols();
  options.params.validate();
  if (g < 2) throw std::invalid_argument("the condition pipeline needs at least 2 channels");

  PipelineResult res;
  ConditionAlarmChain chain(options.asset_group, series.channel_names, options.estimator, options.params);
  chain.on_observation = options.on_observation;
  res.summary.resize(static_cast<std::size_t>(g));
  for (Eigen::Index c = 0; c < g; ++c) res.summary[static_cast<std::size_t>(c)].name = series.channel_names[static_cast<std::size_t>(c)];
  std::vector<bool> first_active(static_cast<std::size_t>(g), false);
  res.feature_z = Eigen::MatrixXd::Constant(n, g, kNaN);
  res.innovation_z = Eigen::MatrixXd::Constant(n, g, kNaN);

  ChainOutput out;
  auto absorb = [&]() {
    for (auto& e : out.events) {
      if (e.category != category::kDegradation) {  // operating changes and lost input are reported, not faults
        if (e.state == AlarmState::Raised) ++(e.category == category::kHealth ? res.input_losses : res.operating_changes);
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
    out.events.clear();
  };
  for (Eigen::Index t = 0; t < n; ++t) {
    const Eigen::VectorXd v = series.values.row(t).transpose();
    std::string problem;
    if (!chain.feed(v, series.index[static_cast<std::size_t>(t)], series.discontinuity[static_cast<std::size_t>(t)],
                    series.time_ns[static_cast<std::size_t>(t)], out, &problem)) {
      if (res.refused++ == 0) res.refusal = problem;
    }
    absorb();
    // The engine's latest standardised values after this row (during the estimator's calibration window
    // the row's own observation comes later, all at once: NaN until the engine runs).
    if (chain.engine() != nullptr) {
      for (Eigen::Index c = 0; c < g; ++c) {
        const auto d = chain.engine()->channel_diagnostics(static_cast<int>(c));
        res.feature_z(t, c) = d.feature.last_z;
        res.innovation_z(t, c) = d.innovation.last_z;
      }
    }
  }
  chain.finish(out);
  absorb();
  res.observations = out.observations;
  if (const auto* stream = chain.estimator().condition_stream()) {
    res.noise = stream->noise();
    for (const auto& w : stream->warnings()) res.estimator_notes.push_back(w);
  }
  if (const auto* learned = chain.estimator().condition_structure(); learned != nullptr) {
    if (!learned->order.empty()) {
      std::string order;
      for (int k : learned->order) order += (order.empty() ? "" : " < ") + series.channel_names[static_cast<std::size_t>(k)];
      res.estimator_notes.push_back("causal order learned by VAR-LiNGAM on " + std::to_string(learned->samples) +
                                    " samples: " + order);
    }
    if (!learned->problem.empty()) res.estimator_notes.push_back(learned->problem);
  }
  res.factor_names = chain.factor_names();
  if (const auto* engine = chain.engine()) {
    res.cusum_threshold = engine->cusum_threshold();
    res.nis_threshold = engine->nis_threshold();
    res.not_running = engine->not_running_observations();
    for (Eigen::Index c = 0; c < g; ++c) res.diagnostics.push_back(engine->channel_diagnostics(static_cast<int>(c)));
  }
  for (auto& s : res.summary) {
    s.first_sustained = s.alarmed && (s.first_cleared_index == 0 ||
                                      s.first_cleared_index >= s.first.index + static_cast<std::uint64_t>(options.sustained_observations));
  }
  return res;
}

}  // namespace causal::alarms
