// sensor-sim: simulated vibration frames for many asset groups on DDS. See --help.
#include "sim_node.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  int exit_code = 0;
  auto options = causal::sim::parse_sim_options(argc, argv, exit_code);
  if (!options) return exit_code;
  return causal::dds::run_service(signals, "sensor-sim", options->dds, [&] {
    return std::make_unique<causal::sim::SimNode>(std::move(*options));
  });
}
