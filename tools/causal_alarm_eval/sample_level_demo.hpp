// Sample-level use of the alarm engine, as in the walking-skeleton demo: raw snapshots are replayed
// through the sample-level causal filter (20 kHz, one snapshot after the other, lags restarting at each
// snapshot), factors and innovation statistics are published every `publish_every` samples (like
// causal-estimator's OutcomeFactors blocks: factors, factor_std, nis_mean), and each publication is one
// Observation of the AlarmEngine (mean_nis + factors, no condition features). The baseline is the
// publications of the first `healthy_snapshots` snapshots (AlarmParams::sample_level).
#pragma once

#include <string>
#include <vector>

#include "causal/alarms/alarm_pipeline.hpp"

namespace causal::alarms {

struct SampleLevelOptions {
  std::string asset_group = "group";
  int healthy_snapshots = 3;
  int publish_every = 1024;        // samples per publication (causal-estimator's publish_every)
  int lag_order = 1;
  bool include_self_lags = false;
  int calibration_samples = 4096;  // q, r tuned by maximum likelihood on the first samples of the first snapshot
};

struct SampleLevelResult {
  std::vector<causal::alarms::AlarmEvent> events;
  std::vector<ChannelSummary> summary;
  std::vector<std::string> snapshot_names;
  std::vector<int> publications_per_snapshot;
  // Per publication and channel: mean NIS (for the report).
  Eigen::MatrixXd mean_nis;
  std::vector<std::uint64_t> publication_snapshot;  // which snapshot each publication belongs to
};

SampleLevelResult run_sample_level(const std::string& ims_dir, const SampleLevelOptions& options);

}  // namespace causal::alarms
