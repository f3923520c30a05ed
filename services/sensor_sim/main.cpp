// sensor-sim: simulated vibration frames for many asset groups on DDS. See --help.
#include "plant_node.hpp"
#include "sim_node.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  int exit_code = 0;
  auto options = causal::sim::parse_sim_options(argc, argv, exit_code);
  if (!options) return exit_code;
  if (!options->plants.empty()) {  // condition-level plants that obey approved interventions
    return causal::dds::run_service(signals, "sensor-sim", options->dds, [&] {
      return std::make_unique<causal::sim::PlantNode>(std::move(*options));
    });
  }
  return causal::dds::run_service(signals, "sensor-sim", options->dds, [&] {
    return std::make_unique<causal::sim::SimNode>(std::move(*options));
  });
}
