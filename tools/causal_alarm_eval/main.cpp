// causal-alarm-eval: runs the condition-level alarm pipeline offline over a whole run-to-failure recording
// and prints every alarm event and a summary line per channel. With --check-* options it is the ctest
// "long check": exit status 0 when the recording meets the detection bar, 1 when not, 2 on input errors
// (including condition vectors the estimator refuses, e.g. a channel count its configuration cannot run).
#include <CLI/CLI.hpp>

#include "causal/io/time_format.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <string>

#include "causal/advice/recommender_params.hpp"
#include "causal/alarms/alarm_pipeline.hpp"
#include "causal/config/cli_conventions.hpp"
#include "causal/config/service_options.hpp"
#include "causal/alarms/statistics.hpp"
#include "sample_level_demo.hpp"

using namespace causal::alarms;

namespace {

std::string channel_label(const ConditionSeries& s, int c) {
  return c >= 0 && c < static_cast<int>(s.channel_names.size()) ? s.channel_names[static_cast<std::size_t>(c)] : "unknown";
}

// --sample-level: factor publications of the sample-level filter over raw snapshots (walking-skeleton demo).
int run_sample_level_mode(const std::string& dir, const SampleLevelOptions& so, bool quiet, bool reasons, int check_channel) {
  SampleLevelResult r;
  try {
    r = run_sample_level(dir, so);
  } catch (const std::exception& e) {
    std::cerr << "causal-alarm-eval: " << e.what() << "\n";
    return causal::config::kExitUsage;
  }
  std::printf("causal-alarm-eval --sample-level: %zu snapshots, publish every %d samples, baseline = publications of the "
              "first %d snapshots\n", r.snapshot_names.size(), so.publish_every, so.healthy_snapshots);
  std::size_t row = 0;
  for (std::size_t s = 0; s < r.snapshot_names.size(); ++s) {
    const int np = r.publications_per_snapshot[s];
    std::printf("snapshot %zu %s (%s): %d publications, median mean-NIS per channel:", s, r.snapshot_names[s].c_str(),
                static_cast<int>(s) < so.healthy_snapshots ? "baseline" : "monitored", np);
    for (Eigen::Index c = 0; c < r.mean_nis.cols(); ++c) {
      std::vector<double> v;
      for (int i = 0; i < np; ++i) v.push_back(r.mean_nis(static_cast<Eigen::Index>(row) + i, c));
      std::printf(" %.3g", median(v));
    }
    std::printf("\n");
    row += static_cast<std::size_t>(np);
  }
  if (!quiet)
    for (const auto& e : r.events) {
      std::printf("event publication=%llu snapshot=%llu %-9s %-8s id=%s kind=%s score=%.3f threshold=%.3f root_cause=%d\n",
                  static_cast<unsigned long long>(e.index), static_cast<unsigned long long>(r.publication_snapshot[e.index]),
                  to_string(e.state), to_string(e.severity), e.alarm_id.c_str(), e.kind.c_str(), e.score, e.threshold,
                  e.root_cause_channel + 1);
      if (reasons) std::printf("  reason: %s\n", e.reason.c_str());
    }
  bool ok = true;
  for (std::size_t c = 0; c < r.summary.size(); ++c) {
    const auto& s = r.summary[c];
    if (!s.alarmed) {
      std::printf("summary channel=%s no alarm\n", s.name.c_str());
      if (static_cast<int>(c) + 1 == check_channel) ok = false;
      continue;
    }
    std::printf("summary channel=%s first_alarm_publication=%llu snapshot=%llu kind=%s severity=%s root_cause=bearing%d max_severity=%s\n",
                s.name.c_str(), static_cast<unsigned long long>(s.first.index),
                static_cast<unsigned long long>(r.publication_snapshot[s.first.index]), s.first.kind.c_str(),
                to_string(s.first.severity), s.first.root_cause_channel + 1, to_string(s.max_severity));
    if (static_cast<int>(c) + 1 == check_channel && s.first.root_cause_channel != static_cast<int>(c)) ok = false;
  }
  if (check_channel <= 0) return 0;
  std::printf("CHECK %s\n", ok ? "PASSED" : "FAILED");
  return ok ? causal::config::kExitOk : causal::config::kExitFailed;
}

// What the run found: the chain and its baseline, every event (unless quiet) and a summary line per channel.
void print_run(const ConditionSeries& series, const PipelineResult& res, const PipelineOptions& opt,
               const std::string& estimator_config, const std::string& source, bool quiet, bool print_reasons) {
  const auto n = series.values.rows();
  std::printf("causal-alarm-eval: feature %s, %lld observations, %lld channels, source %s\n", series.feature.c_str(),
              static_cast<long long>(n), static_cast<long long>(series.values.cols()),
              source.c_str());
  std::printf("chain: estimator %s (condition level) -> observation rule -> AlarmEngine; %llu observations judged, "
              "%llu vectors refused, %llu operating changes, %llu ranges of input lost\n", estimator_config.c_str(),
              static_cast<unsigned long long>(res.observations), static_cast<unsigned long long>(res.refused),
              static_cast<unsigned long long>(res.operating_changes), static_cast<unsigned long long>(res.input_losses));
  std::printf("baseline: observations [%d, %d), CUSUM k=%.2f h=%.3f (ARL0 %.3g), NIS window %d threshold %.3f, not running %llu\n",
              opt.params.warmup_observations, opt.params.warmup_observations + opt.params.baseline_observations,
              opt.params.cusum_k, res.cusum_threshold, opt.params.target_arl0, opt.params.nis_window, res.nis_threshold,
              static_cast<unsigned long long>(res.not_running));
  for (std::size_t k = 0; k < res.noise.size(); ++k)
    std::printf("noise outcome %zu: q=%.3g r=%.3g p0=%.3g\n", k + 1, res.noise[k].q, res.noise[k].r, res.noise[k].p0);
  for (const auto& note : res.estimator_notes) std::printf("estimator: %s\n", note.c_str());

  for (std::size_t c = 0; c < res.diagnostics.size(); ++c) {
    const auto& d = res.diagnostics[c];
    std::printf("baseline %s: log-feature median %.4f scale %.4f lag1 %.2f | innovation median %.3f scale %.3f lag1 %.2f\n",
                channel_label(series, static_cast<int>(c)).c_str(), d.feature.baseline_location, d.feature.baseline_scale,
                d.feature.baseline_lag1_autocorr, d.innovation.baseline_location, d.innovation.baseline_scale,
                d.innovation.baseline_lag1_autocorr);
  }
  auto time_of = [&](std::uint64_t index) {
    const auto it = std::lower_bound(series.index.begin(), series.index.end(), index);
    return it == series.index.end() ? series.time_ns.back() : series.time_ns[static_cast<std::size_t>(it - series.index.begin())];
  };
  if (!quiet) {
    for (const auto& e : res.events) {
      std::printf("event index=%llu time=\"%s\" %-9s %-8s id=%s channel=%s kind=%s category=%s score=%.3f threshold=%.3f root_cause=%s confidence=%.2f\n",
                  static_cast<unsigned long long>(e.index), causal::io::format_utc_seconds(time_of(e.index)).c_str(),
                  to_string(e.state), to_string(e.severity), e.alarm_id.c_str(), channel_label(series, e.channel).c_str(),
                  e.kind.c_str(), e.category.c_str(), e.score, e.threshold, channel_label(series, e.root_cause_channel).c_str(),
                  e.root_cause_confidence);
      if (print_reasons) std::printf("  reason: %s\n", e.reason.c_str());
    }
  }

  for (const auto& s : res.summary) {
    if (!s.alarmed) {
      std::printf("summary channel=%s no alarm\n", s.name.c_str());
      continue;
    }
    std::printf("summary channel=%s first_alarm_index=%llu time=\"%s\" kind=%s severity=%s root_cause=%s sustained=%s "
                "cleared_index=%llu max_severity=%s@%llu first_feature_drift_index=%s\n",
                s.name.c_str(), static_cast<unsigned long long>(s.first.index), causal::io::format_utc_seconds(s.first.raised_time_ns).c_str(),
                s.first.kind.c_str(), to_string(s.first.severity), channel_label(series, s.first.root_cause_channel).c_str(),
                s.first_sustained ? "yes" : "no", static_cast<unsigned long long>(s.first_cleared_index),
                to_string(s.max_severity), static_cast<unsigned long long>(s.max_severity_index),
                s.feature_alarmed ? std::to_string(s.first_feature.index).c_str() : "none");
  }

}

// --trace-csv: the standardised feature and innovation z of every observation.
void write_trace(const std::string& trace_csv, const ConditionSeries& series, const PipelineResult& res) {
  const auto n = series.values.rows();
  std::ofstream out(trace_csv);
  out << "index,time";
  for (const auto& c : series.channel_names) out << "," << c << "_feature_z," << c << "_innovation_z";
  out << "\n";
  for (Eigen::Index t = 0; t < n; ++t) {
    out << series.index[static_cast<std::size_t>(t)] << "," << causal::io::format_utc_seconds(series.time_ns[static_cast<std::size_t>(t)]);
    for (Eigen::Index c = 0; c < series.values.cols(); ++c) out << "," << res.feature_z(t, c) << "," << res.innovation_z(t, c);
    out << "\n";
  }
}

// The --check-* options (the ctest long check): 0 when the recording meets the detection bar, 1 when not.
int check_detection(const ConditionSeries& series, const PipelineResult& res, int check_channel, int check_by,
                    int check_quiet_before) {
  if (check_by < 0 && check_quiet_before < 0) return 0;
  bool ok = true;
  if (check_quiet_before >= 0) {
    for (const auto& e : res.events) {
      if (e.category != category::kDegradation) continue;  // operating changes are not alarms
      if (e.index < static_cast<std::uint64_t>(check_quiet_before)) {
        std::printf("CHECK FAILED: %s %s at snapshot %llu, before %d\n", e.alarm_id.c_str(), to_string(e.state),
                    static_cast<unsigned long long>(e.index), check_quiet_before);
        ok = false;
        break;
      }
    }
  }
  if (check_by >= 0) {
    const int c = check_channel - 1;
    if (c < 0 || c >= static_cast<int>(res.summary.size())) {
      std::printf("CHECK FAILED: --check-channel %d out of range\n", check_channel);
      return causal::config::kExitFailed;
    }
    const auto& s = res.summary[static_cast<std::size_t>(c)];
    if (!s.alarmed || s.first.index > static_cast<std::uint64_t>(check_by) || !s.first_sustained || s.first.root_cause_channel != c) {
      std::printf("CHECK FAILED: channel %s needs a sustained alarm with root cause itself by snapshot %d (got %s)\n",
                  s.name.c_str(), check_by,
                  s.alarmed ? ("index " + std::to_string(s.first.index) + ", root cause " + channel_label(series, s.first.root_cause_channel) +
                               (s.first_sustained ? ", sustained" : ", not sustained")).c_str()
                            : "no alarm");
      ok = false;
    }
  }
  std::printf("CHECK %s\n", ok ? "PASSED" : "FAILED");
  return ok ? causal::config::kExitOk : causal::config::kExitFailed;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Offline condition-level alarm evaluation through the services' chain: features -> causal-estimator's condition pipeline -> alarm-recommender's observation rule -> alarm engine"};
  causal::config::add_version_flag(app);
  std::string table, ims_dir, feature = "meanabs", group = "ims", trace_csv;
  PipelineOptions opt;
  bool quiet = false, print_reasons = false;
  int check_channel = 0, check_by = -1, check_quiet_before = -1;  // check_channel 0 = no check
  auto* src = app.add_option_group("source", "where the condition features come from");
  src->add_option("--features", table,
                  "feature table CSV (derived_per_file_stats or merged_dataset style, or a causal-recorder "
                  "conditions_<group>_<feature>.csv; '-' = stdin)");
  src->add_option("--ims-dir", ims_dir, "raw IMS snapshot directory (features computed with causal_io)");
  src->require_option(1);
  app.add_option("--feature-name,--feature", feature,
                 "condition feature: rms, meanabs, kurtosis, peak ('' = merged_dataset columns)")
      ->capture_default_str();
  app.add_option("--asset-group", group, "asset-group id used in alarm ids");
  // The alarm parameters are alarms.yaml's condition_level section, read by alarm-recommender's own loader; the
  // options below override single values of it.
  std::string alarms_config;
  const causal::config::ConfigFileOption alarms_file(
      app, "--alarms-config", alarms_config, "alarms.yaml",
      "alarm-recommender's parameter file (its condition_level section is the alarm engine's parameters)");
  AlarmParams cli;  // the overrides, applied over the file's values when given
  auto* warmup = app.add_option("--warmup", cli.warmup_observations, "observations ignored at the start (default: alarms file)");
  auto* baseline = app.add_option("--baseline", cli.baseline_observations, "healthy baseline length in observations (default: alarms file)");
  std::string estimator_config = shipped_estimator_config();
  app.add_option("--estimator-config", estimator_config,
                 "causal-estimator's parameter file: the condition-level model the services run")->capture_default_str();
  auto* arl0 = app.add_option("--target-arl0", cli.target_arl0, "in-control ARL of the CUSUM detectors (default: alarms file)");
  auto* advisory = app.add_option("--advisory-ratio", cli.advisory_ratio,
                                  "size floor of every degradation alarm: level / baseline (1 = none; default: alarms file)");
  auto* window = app.add_option("--level-window", cli.level_window,
                                "observations whose median is a channel's level (and for which the size floor must "
                                "hold; default: alarms file)");
  app.add_flag("--quiet", quiet, "print only the summary (not every event)");
  app.add_flag("--reasons", print_reasons, "print each event's plain-language reason");
  app.add_option("--trace-csv", trace_csv, "write per-observation standardised feature / innovation z to this CSV");
  app.add_option("--check-channel", check_channel, "1-based channel that must alarm (with root cause itself)");
  app.add_option("--check-by", check_by, "it must raise a sustained alarm no later than this snapshot index");
  app.add_option("--check-quiet-before", check_quiet_before, "no alarm of any kind before this snapshot index");
  bool sample_level = false;
  SampleLevelOptions so;
  app.add_flag("--sample-level", sample_level, "sample-level mode over raw snapshots (needs --ims-dir)");
  app.add_option("--healthy-snapshots", so.healthy_snapshots, "sample level: snapshots that form the baseline")->capture_default_str();
  app.add_option("--publish-every", so.publish_every, "sample level: samples per factor publication")->capture_default_str();
  app.add_option("--lag-order", so.lag_order, "sample level: lag order M of the causal model")->capture_default_str();
  app.add_flag("--self-lags", so.include_self_lags, "sample level: include y_k[n-l] regressors for outcome k");
  CAUSAL_CLI_PARSE(app, argc, argv);
  if (sample_level) {
    if (ims_dir.empty()) {
      std::cerr << "causal-alarm-eval: --sample-level needs --ims-dir\n";
      return causal::config::kExitUsage;
    }
    so.asset_group = group;
    return run_sample_level_mode(ims_dir, so, quiet, print_reasons, check_by >= 0 || check_channel > 0 ? check_channel : 0);
  }
  opt.asset_group = group;

  ConditionSeries series;
  PipelineResult res;
  try {
    alarms_file.require(alarms_config);
    opt.params = causal::advice::load_recommender_params(alarms_config).condition;
    if (*warmup) opt.params.warmup_observations = cli.warmup_observations;
    if (*baseline) opt.params.baseline_observations = cli.baseline_observations;
    if (*arl0) opt.params.target_arl0 = cli.target_arl0;
    if (*advisory) opt.params.advisory_ratio = cli.advisory_ratio;
    if (*window) opt.params.level_window = cli.level_window;
    opt.params.validate();
    opt.estimator = load_estimator_config(estimator_config);
    series = table.empty() ? series_from_ims_directory(ims_dir, feature, !quiet, opt.params.gap_multiple)
                           : series_from_feature_table(table, feature, opt.params.gap_multiple);
    res = run_condition_pipeline(series, opt);
  } catch (const std::exception& e) {
    std::cerr << "causal-alarm-eval: " << e.what() << "\n";
    return causal::config::kExitUsage;
  }

  if (res.refused > 0) {  // loudly, as the estimator would (it exits 4): nothing judged on those vectors
    std::cerr << "causal-alarm-eval: the estimator refused " << res.refused << " of " << series.values.rows()
              << " condition vectors: " << res.refusal << "\n";
  }
  print_run(series, res, opt, estimator_config, table.empty() ? ims_dir : table, quiet, print_reasons);
  if (!trace_csv.empty()) write_trace(trace_csv, series, res);
  if (res.refused > 0) return causal::config::kExitUsage;
  return check_detection(series, res, check_channel, check_by, check_quiet_before);
}
