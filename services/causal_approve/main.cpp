// causal-approve: an operator approves one recommended lever; published as an intervention. See --help.
#include "approve_node.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::approve::ApproveOptions o;
  CLI::App app{
      "causal-approve: approves one recommendation of alarm-recommender (a reliable upstream lever) and publishes it\n"
      "as an intervention on causal_twin/intervention: the lever channel's level changed by the recommended\n"
      "percent for --duration snapshots from --start-index. The plant's actuator (sensor-sim in simulation) applies\n"
      "it, causal-recorder records it (interventions.csv), alarm-recommender checks its outcome. It publishes only\n"
      "the one recommendation named, and only for the group named. It prints one line\n"
      "  approved <request id>: <group> channel <j> level <percent> for <n> snapshots from snapshot <index> ...\n"
      "Exit codes: 0 published and acknowledged by every reader, 2 bad arguments, 3 recommendation not found, no\n"
      "intervention reader, or not acknowledged in time, 4 the recommendation is not an approvable lever."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--group", o.asset_group, "asset group the recommendation is for")->required();
  app.add_option("--recommendation", o.recommendation_id, "recommendation id (as published, e.g. <alarm id>/1)")
      ->required();
  app.add_option("--user", o.user, "who approves it (recorded with the intervention)")->required();
  app.add_option("--start-index", o.start_index,
                 "first snapshot index the change applies to (default: the group's latest snapshot, from the source's "
                 "condition inputs or else the estimator's condition vectors, + --lead)");
  app.add_option("--lead", o.lead, "snapshots between the latest one seen and the default start")
      ->check(CLI::Range(1, 100000))->capture_default_str();
  app.add_option("--duration", o.duration,
                 "snapshots the change is held for (default: the recommendation's horizon, at least 12)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--wait-for", o.wait_for,
                 "participant name whose intervention reader must be matched before publishing (repeatable), e.g. "
                 "sensor-sim");
  app.add_option("--timeout", o.timeout_s, "seconds to find the recommendation, the readers and their acknowledgement")
      ->check(CLI::PositiveNumber)->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  return causal::dds::run_service(signals, "causal-approve", o.dds,
                                  [&] { return std::make_unique<causal::approve::ApproveNode>(std::move(o)); });
}
