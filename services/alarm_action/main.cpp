// causal-alarm-action: acknowledges, shelves or unshelves one alarm of the running twin (ISA-18.2 alarm
// management) and waits for alarm-recommender's result. See --help.
#include "action_node.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::alarm_action::ActionOptions o;
  CLI::App app{"causal-alarm-action: acknowledges, shelves (for MINUTES, with a reason) or unshelves one alarm of the\n"
               "running twin; alarm-recommender applies it and answers. Shelving covers the alarm's source (asset\n"
               "group, channel, detector), ends by itself after MINUTES (wall clock), at most a week.\n"
               "Exit codes: 0 applied, 2 usage error, 3 no alarm-recommender / no result in time, 4 refused\n"
               "(unknown alarm id, already acknowledged, not shelved, ...)."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--group", o.asset_group, "asset group of the alarm, e.g. ims2-shaft1")->required();
  app.add_option("--alarm", o.alarm_id, "alarm id, e.g. ims2-shaft1/1/feature_drift/0")->required();
  auto* ack = app.add_flag("--ack", o.acknowledge, "acknowledge the alarm");
  auto* shelve = app.add_option("--shelve", o.shelve_minutes, "shelve the alarm's source for MINUTES (> 0, <= 10080)")
                     ->check(CLI::Range(1e-6, 10080.0));
  auto* unshelve = app.add_flag("--unshelve", o.unshelve, "lift a shelving now");
  ack->excludes(shelve)->excludes(unshelve);
  shelve->excludes(unshelve);
  app.add_option("--user", o.user, "who acts (recorded with the action)")->required();
  app.add_option("--reason", o.reason, "why (required with --shelve)");
  app.add_option("--timeout", o.timeout_s, "seconds to wait for the recommender and its result")
      ->check(CLI::PositiveNumber)->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  if (ack->count() + shelve->count() + unshelve->count() != 1) {
    std::fprintf(stderr, "causal-alarm-action: give exactly one of --ack, --shelve MINUTES and --unshelve\n");
    return causal::config::kExitUsage;
  }
  if (shelve->count() > 0 && o.reason.empty()) {
    std::fprintf(stderr, "causal-alarm-action: --shelve needs --reason TEXT\n");
    return causal::config::kExitUsage;
  }
  return causal::dds::run_service(signals, "causal-alarm-action", o.dds,
                                  [&] { return std::make_unique<causal::alarm_action::ActionNode>(std::move(o)); });
}
