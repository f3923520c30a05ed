// alarm-recommender: causal factors in; alarms, root cause and recommendations out. See --help.
#include "recommender_node.hpp"
#include "causal/dds/source_driver.hpp"

#include "causal/config/service_options.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"
#include <stdexcept>
#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::recommender::RecommenderOptions o;
  std::string actions_file;
  CLI::App app{"alarm-recommender: learns each asset group's healthy baseline, raises explained alarms with their\n"
               "root cause from the causal factors and innovations, and publishes them."};
  causal::dds::add_common_options(app, o.dds);
  const causal::config::ConfigFileOption params(app, "--params", o.params_file, "alarms.yaml", "YAML parameter file");
  const causal::config::ConfigFileOption actions(
      app, "--actions", actions_file, "actions.yaml",
      "YAML action catalogue (what to do on an alarmed asset, by asset type and severity)");
  app.add_option("--idle-exit", o.idle_exit_s, "exit once data has arrived, every publisher of factors/condition vectors has left, and nothing arrived for this many seconds (0 = never)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  causal::config::add_max_runtime_option(app, o.max_runtime_s);
  app.add_option("--state-dir", o.state_dir,
                 "directory for crash/restart checkpoints of the alarm engines, one file per asset group and time "
                 "scale (<group>.<condition|sample>.alarms.state): baselines, detectors, alarm id counters, active "
                 "alarms and the last event of every alarm, re-published at restart; re-sent observations are "
                 "dropped. Empty = no persistence")
      ->capture_default_str();
  causal::dds::add_wait_for_option(app, o.wait_for,
                                   "before processing, wait until readers of these participants are matched on the "
                                   "alarm, recommendation, asset-status and prognosis topics (input queues meanwhile; "
                                   "without it a historian that starts late gets only the last 64 changes per key)",
                                   "causal-recorder");
  app.add_option("--wait-timeout", o.wait_timeout_s, "give up waiting for readers after this many seconds (exit 3)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  return causal::dds::run_service(signals, "alarm-recommender", o.dds, [&] {
    params.require(o.params_file);
    auto loaded = causal::advice::load_recommender_params(o.params_file);
    actions.require(actions_file);
    loaded.actions = causal::advice::load_action_catalogue(actions_file);
    return std::make_unique<causal::recommender::RecommenderNode>(std::move(o), std::move(loaded));
  });
}
