#include "ingest_options.hpp"

#include <arpa/inet.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <stdexcept>

#include "causal/dds/typed_endpoints.hpp"

namespace causal::ingest {

const char* source_kind_name(SourceKind kind) {
  switch (kind) {
    case SourceKind::Mqtt:
      return "mqtt";
    case SourceKind::Udp:
      return "udp";
    case SourceKind::Stdin:
      return "stdin";
  }
  return "?";
}

namespace {
// "HOST:PORT" -> host, port (1..65535).
void host_port(const std::string& text, const std::string& whole, SourceSpec& s) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw std::invalid_argument("--source '" + whole + "': HOST:PORT expected");
  s.host = text.substr(0, colon);
  try {
    std::size_t used = 0;
    s.port = std::stoi(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) throw std::invalid_argument("port");
  } catch (const std::exception&) {
    throw std::invalid_argument("--source '" + whole + "': the port is not a number");
  }
  if (s.port < 1 || s.port > 65535) throw std::invalid_argument("--source '" + whole + "': port out of range");
}
}  // namespace

SourceSpec parse_source(const std::string& text) {
  SourceSpec s;
  s.text = text;
  if (text == "-") return s;
  if (text.rfind("mqtt://", 0) == 0) {
    s.kind = SourceKind::Mqtt;
    const std::string rest = text.substr(7);
    const auto slash = rest.find('/');
    if (slash == std::string::npos || slash + 1 >= rest.size()) {
      throw std::invalid_argument("--source '" + text + "': mqtt://HOST:PORT/TOPIC expected");
    }
    host_port(rest.substr(0, slash), text, s);
    s.topics.push_back(rest.substr(slash + 1));
    return s;
  }
  if (text.rfind("udp://", 0) == 0) {
    s.kind = SourceKind::Udp;
    host_port(text.substr(6), text, s);
    return s;
  }
  throw std::invalid_argument("--source '" + text + "': mqtt://HOST:PORT/TOPIC, udp://HOST:PORT or - (stdin) expected");
}

Ipv4Network parse_ipv4_network(const std::string& text) {
  Ipv4Network n;
  const auto slash = text.find('/');
  const std::string address = text.substr(0, slash);
  in_addr a{};
  if (::inet_pton(AF_INET, address.c_str(), &a) != 1) {
    throw std::invalid_argument("--udp-allow '" + text + "': expected A.B.C.D or A.B.C.D/N");
  }
  n.address = ntohl(a.s_addr);
  if (slash != std::string::npos) {
    const std::string bits = text.substr(slash + 1);
    if (bits.empty() || bits.size() > 2 || bits.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(bits) > 32) {
      throw std::invalid_argument("--udp-allow '" + text + "': the prefix length must be 0..32");
    }
    n.prefix = std::stoi(bits);
  }
  return n;
}

namespace {

// The MQTT source's options (session, QoS, TLS and credentials).
void add_mqtt_options(CLI::App& app, IngestOptions& o) {
  app.add_option("--mqtt-qos", o.mqtt_qos,
                 "MQTT subscription QoS (1: at least once; duplicates are rejected by sequence)")
      ->check(CLI::Range(0, 2))
      ->capture_default_str();
  app.add_option("--client-id", o.mqtt_client_id, "MQTT client id (default sensor-ingest-<pid>)");
  app.add_flag("--mqtt-keep-session", o.mqtt_keep_session,
               "keep the MQTT session at the broker (clean session off; needs --client-id and --mqtt-qos 1 or 2): "
               "messages published while sensor-ingest is down are queued by the broker and delivered at its restart");
  app.add_option("--mqtt-cafile", o.mqtt_security.ca_file,
                 "connect to the broker over TLS, trusting this CA (PEM); the broker's name must match its certificate")
      ->check(CLI::ExistingFile);
  app.add_option("--mqtt-cert", o.mqtt_security.cert_file, "client certificate for mutual TLS (PEM, with --mqtt-key)")
      ->check(CLI::ExistingFile);
  app.add_option("--mqtt-key", o.mqtt_security.key_file, "the client certificate's private key (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--mqtt-username", o.mqtt_security.username, "MQTT user name (with --mqtt-password-file)");
  app.add_option("--mqtt-password-file", o.mqtt_security.password_file,
                 "file (mode 0600) whose first line is the MQTT password")
      ->check(CLI::ExistingFile);
}

}  // namespace

std::optional<IngestOptions> parse_ingest_options(int argc, char** argv, int& exit_code) {
  IngestOptions o;
  std::string source;
  std::vector<std::string> topics;
  CLI::App app{
      "sensor-ingest: publishes real sensor data as vibration frames (causal_twin/vibration_frame) on DDS, from\n"
      "an MQTT broker, UDP datagrams or stdin. One message is one block of N samples x G channels of one asset\n"
      "group; three encodings, told apart by their first byte, are accepted on every source:\n"
      "  JSON  {\"asset_group\":\"pump-1\",\"channels\":[\"b1\",\"b2\"],\"sample_rate_hz\":20000,\n"
      "         \"t0_ns\":1700000000000000000,\"sequence\":17,\"samples\":[[0.1,0.2],[0.3,0.4]]}\n"
      "        optional \"unit\":\"g\", \"end_of_segment\":true; null is a missing value (NaN). One per line on "
      "stdin.\n"
      "  CSV   a header line, then N lines of G comma-separated numbers:\n"
      "        #block asset_group=pump-1 channels=b1,b2 sample_rate_hz=20000 t0_ns=1700000000000000000 sequence=17 "
      "samples=2\n"
      "        optional words unit=g end_of_segment=1; nan is a missing value.\n"
      "  binary little-endian: \"CTB1\", u16 G, u16 flags (bit 0 end_of_segment), u32 N, u64 sequence, i64 t0_ns,\n"
      "        f64 sample_rate_hz; then u16 length + bytes of the asset group, the unit and each of the G channel\n"
      "        names; then N x G f64 samples, sample-major.\n"
      "t0_ns is the source's time of the first sample (ns since the Unix epoch, UTC), sequence the source's block\n"
      "counter. Per asset group the frames get gap-free sequence numbers; a gap in the source's sequence or time\n"
      "(more than --gap-factor sample periods between two samples), a restarted sequence, a new sample rate or\n"
      "the block after end_of_segment is published as a discontinuity (lags restart; a new snapshot index).\n"
      "Rejected and counted, never fatal: malformed, truncated, shape (wrong channel count), field, oversize,\n"
      "layout_change (other channels than before), duplicate (sequence seen), out_of_order (time overlaps).\n"
      "NaN/Inf values are forwarded and counted: the estimator screens them per channel (data_quality alarm).\n"
      "Ready-made condition features (one value per channel, one message per snapshot) go onto\n"
      "causal_twin/condition_input instead, with the same rejections and counts; sequence is the snapshot index:\n"
      "  {\"asset_group\":\"pump-1\",\"feature\":\"meanabs\",\"channels\":[\"b1\",\"b2\"],\"time_ns\":1700000000000000000,\n"
      "   \"sequence\":17,\"values\":[0.12,0.31]}   (optional \"discontinuity\":true)\n"
      "  #features asset_group=pump-1 feature=meanabs channels=b1,b2 time_ns=1700000000000000000 sequence=17 "
      "values=0.12,0.31\n"
      "MQTT (--mqtt-qos, default 1) connects and reconnects by itself (every second) and subscribes again on\n"
      "every connect; UDP takes one block per datagram (up to 64 KiB). At exit it prints\n"
      "  sensor-ingest: received=<messages> published=<frames> rejected=<messages> lost=<frames> <reason>=<n> ...\n"
      "  ... missed=<source blocks that never reached it across its restart (--state-dir)>\n"
      "Exit codes: 0 done or stopped, 1 DDS or internal error, 2 bad arguments, 3 no reader matched in time,\n"
      "4 a message was rejected, a frame lost or a source block missed. stdin ends at end of input; MQTT and UDP at SIGINT/SIGTERM or\n"
      "--max-runtime."};
  dds::add_common_options(app, o.dds);
  app.add_option("--source", source, "mqtt://HOST:PORT/TOPIC, udp://HOST:PORT (bind address) or - (stdin)")->required();
  app.add_option("--topic", topics, "more MQTT topics to subscribe to (wildcards + and # allowed)");
  add_mqtt_options(app, o);
  std::vector<std::string> allow;
  app.add_option("--udp-allow", allow,
                 "take UDP datagrams only from this sender network, A.B.C.D[/N] (repeatable; default 127.0.0.0/8); "
                 "others are refused and counted");
  app.add_option("--gap-factor", o.gap_factor,
                 "a time gap is more than this many sample periods between two consecutive samples")
      ->check(CLI::Range(1.0, 1e9))
      ->capture_default_str();
  app.add_option("--max-block-values", o.limits.max_values, "largest block, N x G values (oversize beyond)")
      ->check(CLI::Range(1, 1 << 24))
      ->capture_default_str();
  app.add_option("--max-message-bytes", o.limits.max_bytes, "largest encoded message (oversize beyond)")
      ->check(CLI::Range(64, 1 << 28))
      ->capture_default_str();
  app.add_option("--queue", o.queue_messages, "messages held between the source and DDS; when full the source waits")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  dds::add_source_wait_options(app, o.wait, false);
  app.add_option("--write-timeout", o.write_timeout_s,
                 "a frame the readers do not accept within this many seconds is counted lost (exit 4)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--state-dir", o.state_dir,
                 "keep each asset group's frame numbering in DIR/<group>.ingest.state, so a restarted sensor-ingest "
                 "continues it (without it a restart numbers from 0 again and the estimator refuses that input); "
                 "source blocks sent while it was down and never taken skip their frame numbers (missed=, exit 4)");
  app.add_option("--backlog", o.backlog_frames,
                 "frames kept per asset group (in memory) and resent to a causal-estimator that appears after a "
                 "restart, from the snapshot after the last one it published; 0 = none (a restarted estimator then "
                 "counts what it missed as lost)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
  app.add_option("--max-runtime", o.max_runtime_s, "stop after this many seconds in any case (0 = no bound)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  try {
    app.parse(argc, argv);
    o.source = parse_source(source);
    for (const auto& t : topics) o.source.topics.push_back(t);
    if (!topics.empty() && o.source.kind != SourceKind::Mqtt)
      throw CLI::ValidationError("--topic", "only with an mqtt:// source");
    for (const auto& a : allow) o.udp_allow.push_back(parse_ipv4_network(a));
    if (o.udp_allow.empty()) o.udp_allow.push_back(parse_ipv4_network("127.0.0.0/8"));
    if (!allow.empty() && o.source.kind != SourceKind::Udp) throw CLI::ValidationError("--udp-allow", "only with a udp:// source");
    if (o.mqtt_keep_session && (o.mqtt_client_id.empty() || o.mqtt_qos == 0 || o.source.kind != SourceKind::Mqtt))
      throw CLI::ValidationError("--mqtt-keep-session", "needs an mqtt:// source, a fixed --client-id and --mqtt-qos 1 or 2");
    const auto& m = o.mqtt_security;
    if (m.cert_file.empty() != m.key_file.empty()) throw CLI::ValidationError("--mqtt-cert", "give --mqtt-key with it");
    if (!m.cert_file.empty() && m.ca_file.empty()) throw CLI::ValidationError("--mqtt-cert", "needs --mqtt-cafile (TLS)");
    if (m.username.empty() != m.password_file.empty())
      throw CLI::ValidationError("--mqtt-username", "give --mqtt-username and --mqtt-password-file together");
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e);
    if (exit_code != 0) exit_code = 2;
    return std::nullopt;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s\n", e.what());
    exit_code = 2;
    return std::nullopt;
  }
  if (o.mqtt_client_id.empty()) o.mqtt_client_id = "sensor-ingest-" + std::to_string(::getpid());
  exit_code = 0;
  return o;
}

}  // namespace causal::ingest
