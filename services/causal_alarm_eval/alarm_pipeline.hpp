// Offline condition-level alarm pipeline (no DDS): condition features per snapshot -> causal Kalman
// filter on the standardised log features -> AlarmEngine. Used by causal-alarm-eval and by the
// real-data alarm test, so both judge exactly the same code path.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/noise_params.hpp"

namespace causal::alarm_eval {

// One condition feature per channel and snapshot.
struct ConditionSeries {
  std::vector<std::string> channel_names;  // G
  std::vector<std::int64_t> time_ns;       // N, increasing
  std::vector<std::uint64_t> index;        // N snapshot indices in the run (may skip when files are missing)
  std::vector<bool> discontinuity;         // N: true where the series does not continue the previous row
  Eigen::MatrixXd values;                  // N x G raw feature values (positive scale features)
  std::string feature;                     // "rms", "meanabs", ...
};

// Feature table (derived_per_file_stats style with the feature's column suffix, or merged_dataset style
// when feature is empty). Snapshot index = row number; a time gap larger than 2.5 x the median interval
// is a discontinuity.
ConditionSeries series_from_feature_table(const std::string& path, const std::string& feature);

// Raw IMS snapshot directory: computes the feature of every snapshot with causal_io. The snapshot index is
// the run index derived from the time stamps, round((t - t_first) / period) with period = the smallest
// interval between consecutive files, so a subset keeps the indices of the full run. A gap larger than
// 2.5 x the median interval is a discontinuity (lags restart there).
ConditionSeries series_from_ims_directory(const std::string& dir, const std::string& feature,
                                          bool verbose_progress = false);

struct PipelineOptions {
  std::string asset_group = "group";
  causal::alarms::AlarmParams params;
  int lag_order = 1;
  bool include_self_lags = false;
  // Filter input: log feature centred / scaled by the baseline median / MAD (true), or the plain log
  // feature as causal-estimator's condition level feeds it (false).
  bool standardize_input = true;
  // q, r per outcome tuned by maximum likelihood (causal::tune_noise) on the baseline window; otherwise
  // `noise` is used for every outcome.
  bool tune_noise = true;
  causal::NoiseParams noise{1e-4, 0.5, 1.0};
  // Reporting only: the first alarm of a channel counts as sustained when it is still active at the end
  // of the run or stayed active for at least this many observations.
  int sustained_observations = 36;
  // Called with every observation the engine is fed, in order (e.g. tests that replay the real stream
  // through engines of their own, such as the checkpoint tests). Empty = not called.
  std::function<void(const causal::alarms::Observation&)> on_observation;
};

struct ChannelSummary {
  std::string name;
  bool alarmed = false;
  causal::alarms::AlarmEvent first;     // first Raised event of any kind
  bool first_sustained = false;         // see PipelineOptions::sustained_observations
  std::uint64_t first_cleared_index = 0;  // 0 when never cleared
  causal::alarms::Severity max_severity = causal::alarms::Severity::Advisory;
  std::uint64_t max_severity_index = 0;
  bool feature_alarmed = false;
  causal::alarms::AlarmEvent first_feature;  // first feature_drift Raised event
};

struct PipelineResult {
  std::vector<causal::alarms::AlarmEvent> events;
  std::vector<ChannelSummary> summary;       // G
  std::vector<causal::NoiseParams> noise;    // per outcome, as used
  std::vector<std::string> tuning_messages;  // per outcome (empty when not tuned)
  std::vector<double> baseline_median_log;   // per channel: standardisation of the filter input
  std::vector<double> baseline_scale_log;
  std::uint64_t filter_updates = 0;
  std::uint64_t not_running = 0;             // snapshots withheld from the filter (machine stopped)
  std::uint64_t operating_changes = 0;       // events of category operating_change (in `events`, not in summary)
  double cusum_threshold = 0.0;
  double nis_threshold = 0.0;
  // Per observation and channel (N x G) for plots / diagnostics: standardised feature z, standardised
  // innovation z (NaN when none).
  Eigen::MatrixXd feature_z, innovation_z;
  std::vector<causal::alarms::ChannelDiagnostics> diagnostics;  // per channel, at the end of the run
};

PipelineResult run_condition_pipeline(const ConditionSeries& series, const PipelineOptions& options);

}  // namespace causal::alarm_eval
