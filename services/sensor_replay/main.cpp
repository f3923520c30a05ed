// sensor-replay: publishes recorded vibration data on DDS. See --help.
#include "replay_node.hpp"

#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  int exit_code = 0;
  auto options = causal::replay::parse_replay_options(argc, argv, exit_code);
  if (!options) return exit_code;
  return causal::dds::run_service(signals, "sensor-replay", options->dds, [&] {
    return std::make_unique<causal::replay::ReplayNode>(std::move(*options));
  });
}
