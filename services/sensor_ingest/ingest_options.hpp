// sensor-ingest's parameters: one plain struct, filled and checked by parse_ingest_options().
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "causal/dds/service_runtime.hpp"
#include "ingest_block.hpp"

namespace causal::ingest {

enum class SourceKind { Mqtt, Udp, Stdin };

// --source: mqtt://HOST:PORT/TOPIC, udp://HOST:PORT or "-".
struct SourceSpec {
  SourceKind kind = SourceKind::Stdin;
  std::string host;
  int port = 0;
  std::vector<std::string> topics;  // MQTT: the URL's topic and every --topic
  std::string text;                 // as given, for the log
};

// Parses a --source value; throws std::invalid_argument naming what is wrong.
SourceSpec parse_source(const std::string& text);
const char* source_kind_name(SourceKind kind);  // "mqtt", "udp", "stdin"

struct IngestOptions {
  dds::CommonOptions dds;
  SourceSpec source;
  int mqtt_qos = 1;
  std::string mqtt_client_id;  // default sensor-ingest-<pid>
  double gap_factor = 1.5;     // see block_sequencer.hpp
  BlockLimits limits;
  std::size_t queue_messages = 1024;  // between the source and the DDS writer; a full queue stalls the source
  int wait_subscribers = 1;
  std::vector<std::string> wait_for;  // and readers of these participants: "causal-estimator[:N]"
  double wait_timeout_s = 30.0;
  double write_timeout_s = 10.0;
  double max_runtime_s = 0.0;
  std::string state_dir;  // per-group numbering kept across restarts (ingest_state_store.hpp); empty = none
};

// Parses argv. Returns nullopt after printing --help / an error; `exit_code` tells the caller what to return.
std::optional<IngestOptions> parse_ingest_options(int argc, char** argv, int& exit_code);

}  // namespace causal::ingest
