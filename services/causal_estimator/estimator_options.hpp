// causal-estimator's options (the command line, main.cpp) and the role tag its participant announces.
#pragma once

#include "causal/dds/service_runtime.hpp"
#include "causal/dds/asset_group_filter.hpp"
#include "group_quota.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace causal::estimator {

struct EstimatorOptions {
  dds::CommonOptions dds;
  std::string params_file;
  // The asset groups this estimator owns (every group by default); its readers are filtered to them.
  dds::AssetGroupSelection groups;
  std::string shard_name;  // for logs: the --shard NAME, or "I/N" for a hash slice
  double idle_exit_s = 0.0;    // exit after this long without data, once data has arrived (0 = never)
  double max_runtime_s = 0.0;  // hard stop (0 = none)
  // Wait for readers of participants with these names ("alarm-recommender", or "causal-recorder:1") on the
  // factor topic before processing (input queues meanwhile in the reliable, transient-local readers).
  std::vector<std::string> wait_for;
  double wait_timeout_s = 30.0;
  std::size_t outbound_capacity = 65536;  // messages queued for the DDS writers (OutboundQueue)
  // After a restore from a checkpoint: how long input that does not continue the checkpoint is held (not fed,
  // not dropped) for the source to resend the continuation (sensor-ingest's backlog, sensor-replay's rewind).
  // The wait ends at once when the continuation arrives; when it does not, the held input is fed and the gap
  // counted as lost (input_lost).
  double resume_wait_s = 10.0;
  double stuck_after_s = 3.0;    // a write waiting this long on a reader raises a HEALTH alarm
  bool standby = false;          // hot standby: publish nothing while a primary estimator is alive (StandbyBuffer)
  double takeover_after_s = 6.0; // the primary's absence (> its 5 s lease) after which the standby takes over
  bool verbose = false;  // log every condition-level factor vector (off: progress only)
  double health_deadline_s = 30.0;  // estimator.yaml health.deadline_s (HealthWatch)
  GroupQuotaLimits quota;  // --max-groups, --max-groups-per-writer (group_quota.hpp)
  std::string stage_trace;  // per-frame stage timestamps written here at exit (stage_trace.hpp); empty = off
  std::string state_dir;  // checkpoints (EstimatorStateStore); empty = none
  // estimator.yaml output.factor_messages: false = batch (one message per CausalFactorBatch), true = set (one
  // CausalFactorSet per input on causal_twin/causal_factor_sets).
  bool factor_sets = false;
};

// The role tag an estimator announces (DdsSettings::role_tag): "shard " + its asset-group filter expression
// ("shard " alone when it owns every group). Primary and standby of one shard announce the same tag.
inline std::string shard_role_tag(const dds::AssetGroupSelection& groups) { return "shard " + groups.expression(); }

}  // namespace causal::estimator
