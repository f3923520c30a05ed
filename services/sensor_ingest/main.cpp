// sensor-ingest: real sensor data (MQTT, UDP, stdin) published as vibration frames on DDS. See --help.
#include "ingest_node.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  int exit_code = 0;
  auto options = causal::ingest::parse_ingest_options(argc, argv, exit_code);
  if (!options) return exit_code;
  return causal::dds::run_service(signals, "sensor-ingest", options->dds,
                                  [&] { return std::make_unique<causal::ingest::IngestNode>(std::move(*options)); });
}
