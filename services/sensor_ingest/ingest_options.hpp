// sensor-ingest's parameters: one plain struct, filled and checked by parse_ingest_options().
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "causal/dds/service_runtime.hpp"
#include "causal/dds/source_driver.hpp"
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
[[nodiscard]] SourceSpec parse_source(const std::string& text);
const char* source_kind_name(SourceKind kind);  // "mqtt", "udp", "stdin"

// An IPv4 network a UDP datagram may come from (address and prefix length, host byte order).
struct Ipv4Network {
  std::uint32_t address = 0;
  int prefix = 32;
  bool contains(std::uint32_t a) const {
    const std::uint32_t mask = prefix == 0 ? 0 : ~std::uint32_t{0} << (32 - prefix);
    return (a & mask) == (address & mask);
  }
};
// "A.B.C.D" or "A.B.C.D/N"; throws std::invalid_argument naming the value.
Ipv4Network parse_ipv4_network(const std::string& text);

// How sensor-ingest authenticates to its MQTT broker: TLS (with the broker's CA; a client certificate and key
// for mutual TLS) and/or a user name with a password read from a file.
struct MqttSecurity {
  std::string ca_file;        // "" = no TLS
  std::string cert_file;      // client certificate (mutual TLS), with key_file
  std::string key_file;
  std::string username;
  std::string password_file;  // first line is the password; mode 0600
};

struct IngestOptions {
  dds::CommonOptions dds;
  SourceSpec source;
  int mqtt_qos = 1;
  std::string mqtt_client_id;  // default sensor-ingest-<pid>
  bool mqtt_keep_session = false;  // clean session off: the broker queues QoS >= 1 messages while we are down
  MqttSecurity mqtt_security;
  // UDP datagrams are taken only from these networks (default loopback, 127.0.0.0/8); others are refused and
  // counted (ingest_udp_refused_total).
  std::vector<Ipv4Network> udp_allow;
  double gap_factor = 1.5;     // see block_sequencer.hpp
  BlockLimits limits;
  std::size_t queue_messages = 1024;  // between the source and the DDS writer; a full queue stalls the source
  dds::SourceWaitOptions wait;  // the readers waited for before taking input
  double write_timeout_s = 10.0;
  double max_runtime_s = 0.0;
  std::string state_dir;  // per-group numbering kept across restarts (ingest_state_store.hpp); empty = none
  std::size_t backlog_frames = 600;  // frames kept per asset group for a restarted estimator (frame_backlog.hpp)
};

// Parses argv. Returns nullopt after printing --help / an error; `exit_code` tells the caller what to return.
[[nodiscard]] std::optional<IngestOptions> parse_ingest_options(int argc, char** argv, int& exit_code);

}  // namespace causal::ingest
