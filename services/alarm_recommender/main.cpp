// alarm-recommender: causal factors in; alarms, root cause and recommendations out. See --help.
#include "recommender_node.hpp"
#include "recommender_params.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::recommender::RecommenderOptions o;
  o.params_file = causal::dds::default_dds_dir() + "/../config/alarms.yaml";
  CLI::App app{"alarm-recommender: learns each asset group's healthy baseline, raises explained alarms with their\n"
               "root cause from the causal factors and innovations, and publishes them."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--params", o.params_file, "YAML parameter file")->check(CLI::ExistingFile)->capture_default_str();
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
  CLI11_PARSE(app, argc, argv);
  return causal::dds::run_service(signals, "alarm-recommender", o.dds, [&] {
    auto params = causal::recommender::load_recommender_params(o.params_file);
    return std::make_unique<causal::recommender::RecommenderNode>(std::move(o), std::move(params));
  });
}
