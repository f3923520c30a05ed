// causal-ask: asks the running alarm-recommender a what-if question over DDS. See --help.
#include "ask_node.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::ask::AskOptions o;
  CLI::App app{"causal-ask: asks the running alarm-recommender what happens to every channel of an asset group if\n"
               "one channel is changed, from the live condition-level causal model, and prints its answer.\n"
               "Exit codes: 0 answered, 2 invalid question, 3 no recommender / no reply in time, 4 the recommender\n"
               "cannot answer (unknown asset group, a system that does not settle, ...)."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--asset-group", o.asset_group, "asset group, e.g. ims2-shaft1")->required();
  app.add_option("--intervene", o.channel, "channel to change (1-based)")->required()->check(CLI::Range(1, 64));
  auto* d = app.add_option("--delta", o.delta, "change in model units (log-level when the estimator logs features)");
  auto* p = app.add_option("--percent", o.percent, "change of the channel's level in percent, e.g. -10 (log-level model)");
  d->excludes(p);
  app.add_flag("--impulse", o.impulse,
               "a one-snapshot change (default: sustained, held from now on, the same default as causal-whatif)");
  app.add_option("--timeout", o.timeout_s, "seconds to wait for the recommender and its reply")
      ->check(CLI::PositiveNumber)->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  return causal::dds::run_service(signals, "causal-ask", o.dds,
                                  [&] { return std::make_unique<causal::ask::AskNode>(std::move(o)); });
}
