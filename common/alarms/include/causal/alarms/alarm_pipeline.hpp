// Offline condition-level alarm pipeline (no DDS): condition features per snapshot -> the services' chain
// (causal-estimator's condition-level pipeline, alarm-recommender's observation rule and AlarmEngine:
// causal/alarms/condition_alarm_chain.hpp). Used by causal-alarm-eval and by the real-data alarm tests,
// so they judge exactly the code path of the services.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/estimation/noise_params.hpp"
#include "causal/pipeline/asset_pipeline.hpp"

namespace causal::alarms {

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
// when feature is empty). Snapshot index = row number; a time gap larger than gap_multiple x the median
// interval is a discontinuity (AlarmParams::gap_multiple, the rule sensor-replay applies too).
ConditionSeries series_from_feature_table(const std::string& path, const std::string& feature,
                                          double gap_multiple = causal::alarms::AlarmParams{}.gap_multiple);

// Raw IMS snapshot directory: computes the feature of every snapshot with causal_io. The snapshot index is
// the run index derived from the time stamps, round((t - t_first) / period) with period = the smallest
// interval between consecutive files, so a subset keeps the indices of the full run. A gap larger than
// gap_multiple x the median interval is a discontinuity (lags restart there, the engine re-baselines) and
// advances the index by one: a pause is not missing snapshots.
ConditionSeries series_from_ims_directory(const std::string& dir, const std::string& feature,
                                          bool verbose_progress = false,
                                          double gap_multiple = causal::alarms::AlarmParams{}.gap_multiple);

struct PipelineOptions {
  std::string asset_group = "group";
  // alarm-recommender's condition-level parameters (the shipped alarms.yaml values are the defaults).
  causal::alarms::AlarmParams params;
  // causal-estimator's parameters (load_estimator_config(deploy/config/estimator.yaml)); only the condition
  // level runs. The defaults of the struct are NOT the shipped configuration: load it.
  causal::pipeline::AssetPipelineParams estimator;
  // Reporting only: the first alarm of a channel counts as sustained when it is still active at the end
  // of the run or stayed active for at least this many observations.
  int sustained_observations = 36;
  // Called with every observation the engine is fed, in order (e.g. tests that replay the real stream
  // through engines of their own, such as the checkpoint tests). Empty = not called.
  std::function<void(const causal::alarms::Observation&)> on_observation;
};

// causal-estimator's parameter file, read by the estimator's own loader (throws naming the file and key).
causal::pipeline::AssetPipelineParams load_estimator_config(const std::string& path);
// The shipped estimator.yaml of this source tree (deploy/config/estimator.yaml).
std::string shipped_estimator_config();
// PipelineOptions with the shipped estimator configuration loaded.
PipelineOptions shipped_options(const std::string& asset_group);

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
  std::vector<causal::alarms::AlarmEvent> events;  // every event, operating changes included
  std::vector<ChannelSummary> summary;       // G, degradation alarms only
  std::vector<estimation::NoiseParams> noise;    // per outcome, as used by the estimator's condition filter
  std::vector<std::string> estimator_notes;  // what the estimator learned / worked around (structure, noise)
  std::vector<std::string> factor_names;     // the engine's factors (the estimator's layout, outcome-major)
  std::uint64_t observations = 0;            // observations the engine judged
  std::uint64_t refused = 0;                 // condition vectors the estimator refused
  std::string refusal;                       // why (the first refusal), empty when none
  std::uint64_t not_running = 0;             // observations skipped by the engine's operating-state gate
  std::uint64_t operating_changes = 0;       // events of category operating_change (raised)
  std::uint64_t input_losses = 0;            // health events input_lost (index ranges the series skipped)
  double cusum_threshold = 0.0;
  double nis_threshold = 0.0;
  // Per observation and channel (N x G) for plots / diagnostics: standardised feature z, standardised
  // innovation z (NaN when none).
  Eigen::MatrixXd feature_z, innovation_z;
  std::vector<causal::alarms::ChannelDiagnostics> diagnostics;  // per channel, at the end of the run
};

// The services' chain (causal::alarms::ConditionAlarmChain: estimator pipeline -> observation rule ->
// AlarmEngine) over a whole series, one condition vector per row, as sensor-replay would publish it.
PipelineResult run_condition_pipeline(const ConditionSeries& series, const PipelineOptions& options);

}  // namespace causal::alarms
