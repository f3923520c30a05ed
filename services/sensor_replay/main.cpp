// sensor-replay: publishes recorded vibration data on DDS. See --help.
#include "replay_node.hpp"

#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  int exit_code = 0;
  auto options = causal::replay::parse_replay_options(argc, argv, exit_code);
  if (!options) return exit_code;
  try {
    causal::dds::setup_logging("sensor-replay", options->dds.log_level);
    causal::replay::ReplayNode node(std::move(*options));
    signals.start([&node](int sig) {
      spdlog::info("signal {} received, stopping", sig);
      node.stop();
    });
    return node.run();
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
