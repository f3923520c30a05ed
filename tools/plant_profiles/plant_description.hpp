// A plant description for causal-plant-profiles: which hosts exist, their plant-network address and which
// services (roles) each runs. Read from YAML (deploy/plant/example-plant.yaml) and validated as a whole, so a
// plant engineer sees every problem of the file at once instead of one per run.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace causal::plant {

enum class RoleKind { Sensor, Estimator, Recommender, Recorder, Web, Operator };

// One service on a host. Every role is one DDS participant.
struct Role {
  RoleKind kind = RoleKind::Sensor;
  int shard_index = 0;  // estimator only: this shard of shard_count (0-based)
  int shard_count = 1;
};

struct PlantHost {
  std::string name;       // also the profile's file name: <name>.xml
  std::string address;    // IPv4 address on the plant network (Fast DDS 2.9 whitelists by address)
  std::string interface;  // optional: the interface that holds the address, written as a comment only
  std::vector<Role> roles;
  // Sensor hosts only, optional: the asset groups their sensors may write. make-pki.sh --plant issues the
  // identity sensor_identity(host) granted only these; empty = the shared 'sensor' identity (every group).
  std::vector<std::string> groups;
};

// "sensor-<host name>": the identity of a sensor host that names its asset groups.
inline std::string sensor_identity(const PlantHost& host) { return "sensor-" + host.name; }

// Discovery through a Fast DDS discovery server (fastdds discovery) on one of the hosts instead of unicast
// announcements between every pair of hosts.
struct DiscoveryServer {
  std::string host;  // name of a host in the plant
  int port = 11811;
};

struct PlantDescription {
  int domain_id = 0;
  // PKI folder on every host (deploy/security/make-pki.sh); "off" = an open bus, chosen explicitly.
  std::string security = "/etc/causal-twin/security";
  std::optional<DiscoveryServer> discovery_server;
  std::vector<PlantHost> hosts;
};

struct PlantParseResult {
  PlantDescription plant;
  std::vector<std::string> problems;  // empty = valid; each names the host or key it concerns
  bool ok() const { return problems.empty(); }
};

// Parses and validates a YAML text; `source` names it in the problems ("plant.yaml: hosts[1] ...").
[[nodiscard]] PlantParseResult parse_plant_description(const std::string& yaml_text, const std::string& source);
// Same for a file; a missing or unreadable file is one problem.
[[nodiscard]] PlantParseResult load_plant_description(const std::string& path);

// "sensor", "estimator 1/2", ... as written in the YAML.
std::string role_text(const Role& role);
// True when `text` is a dotted-quad IPv4 address (four decimal octets 0..255, no leading zeros).
bool is_ipv4_address(const std::string& text);
// Largest number of participants (roles) on one host.
int max_participants_per_host(const PlantDescription& plant);

}  // namespace causal::plant
