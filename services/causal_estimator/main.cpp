// causal-estimator: vibration frames in, causal factor vectors out. See --help.
#include "estimator_node.hpp"
#include "causal/dds/source_driver.hpp"
#include "causal/config/exit_codes.hpp"
#include "causal/pipeline/estimator_params.hpp"
#include "shard_assignment.hpp"

#include "causal/config/service_options.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"
#include <stdexcept>
#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::estimator::EstimatorOptions o;
  CLI::App app{"causal-estimator: learns time-varying causal factors between the channels of each asset group\n"
               "(Kalman filter and fixed-lag smoother, sample level and condition level) and publishes them.\n"
               "Exit codes: 0 done, 2 invalid configuration, 3 named readers never matched, 4 data lost or refused."};
  causal::dds::add_common_options(app, o.dds);
  const causal::config::ConfigFileOption params(app, "--params", o.params_file, "estimator.yaml", "YAML parameter file");
  // Shards: either named in a configuration file (the primary way: the operator decides which groups go
  // where) or a hash slice (no configuration: groups spread by a stable hash of their id). Either way the
  // readers are content-filtered, so a shard receives only its own groups.
  int shard_index = 0, shard_count = 1;
  std::string shards_file, shard_name;
  app.add_option("--shards", shards_file,
                 "shard assignment file (deploy/config/shards.yaml: shard name -> asset-group ids or glob patterns); "
                 "with --shard NAME this estimator receives only that shard's groups")
      ->check(CLI::ExistingFile);
  app.add_option("--shard", shard_name, "this estimator's shard name in the --shards file");
  app.add_option("--shard-index", shard_index, "without --shards: this estimator's hash slice (0-based)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--shard-count", shard_count,
                 "without --shards: number of estimators sharing the asset groups by a stable hash of the id")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--idle-exit", o.idle_exit_s, "exit once data has arrived, every publisher of frames/condition vectors has left, and nothing arrived for this many seconds (0 = never)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  causal::config::add_max_runtime_option(app, o.max_runtime_s);
  causal::dds::add_wait_for_option(app, o.wait_for,
                                   "before processing, wait until readers of these participants are matched on the "
                                   "causal-factor topic (input queues meanwhile)",
                                   "alarm-recommender causal-recorder");
  app.add_option("--wait-timeout", o.wait_timeout_s, "give up waiting for readers after this many seconds (exit 3)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--outbound-queue", o.outbound_capacity,
                 "messages queued between the filters and the DDS writers; on overflow the oldest sample-level factor "
                 "message is dropped (counted), condition-level output is never dropped (input waits instead)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_flag("--verbose", o.verbose, "log every condition-level factor vector");
  app.add_flag("--standby", o.standby,
               "hot standby: process the same input as the primary estimator but publish nothing while it is alive; "
               "take over (publishing the recent output the primary may not have sent) once it has been gone for "
               "--takeover-after seconds. Run the sources with --wait-for causal-estimator:2");
  app.add_option("--takeover-after", o.takeover_after_s, "seconds without a primary before the standby takes over")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--stuck-after", o.stuck_after_s,
                 "raise a HEALTH alarm when a reader has kept an output write waiting this many seconds (cleared when "
                 "it acknowledges again)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--stage-trace", o.stage_trace,
                 "write per-frame stage timestamps (received, filtered, queued, written) to this CSV at exit, to find "
                 "where latency goes (docs/scale-and-benchmarks.md); empty = off");
  app.add_option("--state-dir", o.state_dir,
                 "checkpoint every asset group's state here after each snapshot and resume from it after a restart "
                 "(input already processed is skipped); empty = no checkpoints");
  app.add_option("--resume-wait", o.resume_wait_s,
                 "after a restart from --state-dir: how long input that does not continue the checkpoint is held for "
                 "the source to resend the continuation (sensor-ingest's --backlog, sensor-replay's rewind); the wait "
                 "ends as soon as it arrives; when it does not, the held input is fed and the gap counted as lost "
                 "(HEALTH alarm input_lost, exit 4)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--max-groups", o.quota.max_groups,
                 "asset groups this estimator serves at most; input of further groups is refused (counted, HEALTH "
                 "alarm asset_group_quota, exit 4)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--max-groups-per-writer", o.quota.max_groups_per_writer,
                 "new asset groups one DDS writer (one source) may open; beyond, refused as with --max-groups")
      ->check(CLI::PositiveNumber)->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  if (shard_index >= shard_count) {
    std::cerr << "error: --shard-index must be < --shard-count\n";
    return causal::config::kExitUsage;
  }
  if (shards_file.empty() != shard_name.empty()) {
    std::cerr << "error: --shards FILE and --shard NAME go together\n";
    return causal::config::kExitUsage;
  }
  if (!shards_file.empty() && shard_count > 1) {
    std::cerr << "error: --shards/--shard and --shard-index/--shard-count are two ways to shard: choose one\n";
    return causal::config::kExitUsage;
  }
  if (shard_count > 1) {
    o.groups = causal::dds::AssetGroupSelection::hash_slice(shard_index, shard_count);
    o.shard_name = std::to_string(shard_index) + "/" + std::to_string(shard_count);
  }
  return causal::dds::run_service(signals, "causal-estimator", o.dds, [&] {
    params.require(o.params_file);
    if (!shards_file.empty()) {
      o.groups.patterns = causal::estimator::load_shard_assignment(shards_file).patterns_of(shard_name);
      o.shard_name = shard_name;
    }
    auto loaded = causal::pipeline::load_estimator_params(o.params_file);
    o.health_deadline_s = causal::pipeline::load_estimator_health(o.params_file).deadline_s;
    o.factor_sets = causal::pipeline::load_estimator_output(o.params_file).factor_messages ==
                    causal::pipeline::FactorMessages::Set;
    return std::make_unique<causal::estimator::EstimatorNode>(std::move(o), std::move(loaded));
  });
}
