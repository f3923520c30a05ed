// alarm-recommender: causal factors in; alarms, root cause and recommendations out. See --help.
#include "recommender_node.hpp"
#include "causal/dds/source_driver.hpp"

#include "causal/config/config_search.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"
#include <stdexcept>
#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::recommender::RecommenderOptions o;
  // Flag, $CAUSAL_TWIN_CONFIG_DIR, build tree, /etc/causal-twin, <prefix>/share/causal-twin/config (in that order).
  const causal::config::ConfigChoice params_choice =
      causal::config::find_config_file("alarms.yaml", "", causal::config::ConfigKind::Parameters);
  o.params_file = params_choice.path;
  const causal::config::ConfigChoice actions_choice =
      causal::config::find_config_file("actions.yaml", "", causal::config::ConfigKind::Parameters);
  std::string actions_file = actions_choice.path;
  CLI::App app{"alarm-recommender: learns each asset group's healthy baseline, raises explained alarms with their\n"
               "root cause from the causal factors and innovations, and publishes them."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--params", o.params_file, "YAML parameter file; default: " + params_choice.describe("alarms.yaml"))
      ->check(CLI::ExistingFile);
  app.add_option("--actions", actions_file,
                 "YAML action catalogue (what to do on an alarmed asset, by asset type and severity); default: " +
                     actions_choice.describe("actions.yaml"))
      ->check(CLI::ExistingFile);
  app.add_option("--idle-exit", o.idle_exit_s, "exit once data has arrived, every publisher of factors/condition vectors has left, and nothing arrived for this many seconds (0 = never)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--max-runtime", o.max_runtime_s, "exit after this many seconds in any case (0 = never)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
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
    if (o.params_file.empty()) throw std::invalid_argument(params_choice.describe("alarms.yaml") + ": give --params FILE");
    auto params = causal::advice::load_recommender_params(o.params_file);
    if (actions_file.empty()) throw std::invalid_argument(actions_choice.describe("actions.yaml") + ": give --actions FILE");
    params.actions = causal::advice::load_action_catalogue(actions_file);
    return std::make_unique<causal::recommender::RecommenderNode>(std::move(o), std::move(params));
  });
}
