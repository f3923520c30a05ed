#include "plant_description.hpp"

#include "causal/config/yaml_bounds.hpp"
#include "causal/config/yaml_fields.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace causal::plant {
namespace {

// Fast DDS ports: 7400 + 250 * domain + offsets must stay below 65536, hence domains 0..232.
constexpr int kMaxDomainId = 232;

struct Problems {
  std::string source;
  std::vector<std::string>& list;
  void add(const std::string& where, const std::string& what) { list.push_back(source + ": " + where + ": " + what); }
};

bool is_valid_host_name(const std::string& name) {
  // The name becomes a file name and appears in commands: letters, digits, '.', '_', '-' only.
  if (name.empty() || name.size() > 63 || !std::isalnum(static_cast<unsigned char>(name.front()))) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
  });
}

std::vector<int> octets(const std::string& address) {
  std::vector<int> out;
  std::stringstream in(address);
  std::string part;
  while (std::getline(in, part, '.')) out.push_back(std::stoi(part));
  return out;
}

// Why an IPv4 address cannot be a plant host's address, or "" when it can.
std::string unusable_address_reason(const std::string& address) {
  const std::vector<int> o = octets(address);
  if (o[0] == 0) return "is not a host address (0.x.x.x)";
  if (o[0] == 127) return "is a loopback address: it reaches no other host (one host: use deploy/dds/localhost.xml)";
  if (o[0] >= 224 && o[0] <= 239) return "is a multicast address; give the host's unicast address";
  if (o[0] >= 240) return "is a reserved or broadcast address";
  return "";
}

bool parse_role(const std::string& text, Role& role) {
  static const std::map<std::string, RoleKind> kinds = {
      {"sensor", RoleKind::Sensor},     {"estimator", RoleKind::Estimator}, {"recommender", RoleKind::Recommender},
      {"recorder", RoleKind::Recorder}, {"web", RoleKind::Web},             {"operator", RoleKind::Operator}};
  std::istringstream in(text);
  std::string word, shard, rest;
  in >> word >> shard >> rest;
  const auto kind = kinds.find(word);
  if (kind == kinds.end() || !rest.empty()) return false;
  role = Role{};
  role.kind = kind->second;
  if (shard.empty()) return true;
  if (role.kind != RoleKind::Estimator) return false;
  // "estimator K/N": shard K of N.
  const auto slash = shard.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == shard.size()) return false;
  const std::string k = shard.substr(0, slash), n = shard.substr(slash + 1);
  const auto digits = [](const std::string& s) {
    return s.size() <= 4 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(k) || !digits(n)) return false;
  role.shard_index = std::stoi(k);
  role.shard_count = std::stoi(n);
  return role.shard_count >= 1 && role.shard_index < role.shard_count;
}

void check_keys(const YAML::Node& map, const std::set<std::string>& known, const std::string& where, Problems& p) {
  for (const auto& entry : map) {
    const std::string key = entry.first.as<std::string>();
    if (known.count(key) == 0) p.add(where, "unknown key '" + key + "'");
  }
}

// The asset groups a sensor host may write (its identity's grant: deploy/security/make-pki.sh --plant).
// A required text field: into `out`, or false with `missing` noted when the key is absent or not a scalar.
bool read_scalar(const YAML::Node& node, const char* key, std::string& out, const std::string& where,
                 const std::string& missing, Problems& p) {
  if (!node[key] || !node[key].IsScalar()) {
    p.add(where, missing);
    return false;
  }
  out = node[key].as<std::string>();
  return true;
}

void parse_groups(const YAML::Node& node, const std::string& label, PlantHost& host, Problems& p) {
  if (!node) return;
  if (!node.IsSequence() || node.size() == 0) {
    p.add(label, "'groups' must be a list of asset groups (the ones this host's sensors may write)");
    return;
  }
  for (const auto& g : node) {
    const std::string name = g.IsScalar() ? g.as<std::string>() : std::string();
    if (name.empty() || name.size() > 200 || !is_valid_host_name(name)) {
      p.add(label, "asset group '" + name + "': 1..200 letters, digits, '.', '_', '-' (named literally in the grant)");
      continue;
    }
    host.groups.push_back(name);
  }
  const bool sensor = std::any_of(host.roles.begin(), host.roles.end(), [](const Role& r) { return r.kind == RoleKind::Sensor; });
  if (!sensor) p.add(label, "'groups' is for hosts with the role 'sensor' (the asset groups their identity may write)");
}

void parse_host(const YAML::Node& node, const std::string& where, PlantHost& host, Problems& p) {
  if (!node.IsMap()) {
    p.add(where, "must be a map with name, address and roles");
    return;
  }
  check_keys(node, {"name", "address", "interface", "roles", "groups"}, where, p);
  if (read_scalar(node, "name", host.name, where, "missing 'name'", p) && !is_valid_host_name(host.name)) {
    p.add(where, "name '" + host.name + "': letters, digits, '.', '_', '-' only (it names the profile file)");
  }
  const std::string label = host.name.empty() ? where : where + " (" + host.name + ")";
  if (read_scalar(node, "address", host.address, label,
                  "missing 'address' (the host's IPv4 address on the plant network)", p)) {
    if (!is_ipv4_address(host.address)) {
      p.add(label, "address '" + host.address + "' is not an IPv4 address (a.b.c.d)");
    } else if (const std::string why = unusable_address_reason(host.address); !why.empty()) {
      p.add(label, "address " + host.address + " " + why);
    }
  }
  if (node["interface"]) host.interface = node["interface"].as<std::string>();
  const YAML::Node roles = node["roles"];
  if (!roles || !roles.IsSequence() || roles.size() == 0) {
    p.add(label, "missing 'roles': a list of sensor, estimator [K/N], recommender, recorder, web, operator");
    return;
  }
  for (const auto& r : roles) {
    Role role;
    const std::string text = r.IsScalar() ? r.as<std::string>() : std::string("(not a word)");
    if (!r.IsScalar() || !parse_role(text, role)) {
      p.add(label, "unknown role '" + text + "' (sensor, estimator, estimator K/N with K < N, recommender, recorder, "
                   "web, operator)");
      continue;
    }
    const bool twice = std::any_of(host.roles.begin(), host.roles.end(), [&](const Role& other) {
      return role_text(other) == role_text(role);
    });
    if (twice) p.add(label, "role '" + text + "' given twice");
    host.roles.push_back(role);
  }
  parse_groups(node["groups"], label, host, p);
}

// Plant-wide rules: unique names and addresses, the services a pipeline needs, complete estimator shards.
void check_plant(const PlantDescription& plant, Problems& p) {
  std::map<std::string, int> names, addresses;
  for (const auto& h : plant.hosts) {
    if (!h.name.empty() && ++names[h.name] == 2) p.add("hosts", "duplicate host name '" + h.name + "'");
    if (!h.address.empty() && ++addresses[h.address] == 2) {
      p.add("hosts", "duplicate address " + h.address + " (two hosts cannot share one; two roles on one host can)");
    }
  }
  const auto count = [&](RoleKind kind) {
    int n = 0;
    for (const auto& h : plant.hosts)
      for (const auto& r : h.roles) n += r.kind == kind ? 1 : 0;
    return n;
  };
  if (count(RoleKind::Sensor) == 0) p.add("hosts", "no host has the role 'sensor': nothing would feed the estimator");
  if (count(RoleKind::Estimator) == 0) p.add("hosts", "no host has the role 'estimator'");
  if (count(RoleKind::Recommender) == 0) p.add("hosts", "no host has the role 'recommender': no alarms would be raised");
  std::set<int> counts;
  std::map<int, int> shards;
  for (const auto& h : plant.hosts)
    for (const auto& r : h.roles)
      if (r.kind == RoleKind::Estimator) {
        counts.insert(r.shard_count);
        ++shards[r.shard_index];
      }
  if (counts.size() > 1) {
    p.add("hosts", "estimator shards disagree on the shard count (every estimator must say K/N with the same N)");
  } else if (counts.size() == 1) {
    const int n = *counts.begin();
    for (int k = 0; k < n; ++k) {
      if (shards[k] == 0) p.add("hosts", "estimator shard " + std::to_string(k) + "/" + std::to_string(n) +
                                             " is on no host: its asset groups would not be estimated");
      if (shards[k] > 1) p.add("hosts", "estimator shard " + std::to_string(k) + "/" + std::to_string(n) +
                                            " is on " + std::to_string(shards[k]) + " hosts");
    }
  }
  if (plant.discovery_server && names.count(plant.discovery_server->host) == 0) {
    p.add("discovery_server.host", "'" + plant.discovery_server->host + "' is not one of the hosts");
  }
}

}  // namespace

bool is_ipv4_address(const std::string& text) {
  int parts = 0;
  std::size_t i = 0;
  while (i <= text.size()) {
    const std::size_t end = text.find('.', i);
    const std::string part = text.substr(i, end == std::string::npos ? std::string::npos : end - i);
    if (part.empty() || part.size() > 3 || (part.size() > 1 && part[0] == '0')) return false;
    if (!std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; })) return false;
    if (std::stoi(part) > 255) return false;
    ++parts;
    if (end == std::string::npos) break;
    i = end + 1;
  }
  return parts == 4;
}

std::string role_text(const Role& role) {
  switch (role.kind) {
    case RoleKind::Sensor: return "sensor";
    case RoleKind::Estimator:
      return role.shard_count == 1 ? "estimator"
                                   : "estimator " + std::to_string(role.shard_index) + "/" + std::to_string(role.shard_count);
    case RoleKind::Recommender: return "recommender";
    case RoleKind::Recorder: return "recorder";
    case RoleKind::Web: return "web";
    case RoleKind::Operator: return "operator";
  }
  return "?";
}

int max_participants_per_host(const PlantDescription& plant) {
  std::size_t most = 0;
  for (const auto& h : plant.hosts) most = std::max(most, h.roles.size());
  return static_cast<int>(most);
}

PlantParseResult parse_plant_description(const std::string& yaml_text, const std::string& source) {
  PlantParseResult result;
  Problems p{source, result.problems};
  YAML::Node root;
  try {
    config::check_yaml_bounds(yaml_text, source);  // no anchors or aliases, bounded depth and size
  } catch (const config::ConfigError& e) {
    result.problems.push_back(e.what());
    return result;
  }
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    p.add("YAML", e.what());
    return result;
  }
  if (!root.IsMap()) {
    p.add("top level", "must be a map with domain, security and hosts");
    return result;
  }
  try {
    check_keys(root, {"domain", "security", "discovery_server", "hosts"}, "top level", p);
    PlantDescription& plant = result.plant;
    if (!root["domain"]) {
      p.add("domain", "missing (the DDS domain id of the plant, 0..232)");
    } else {
      long domain = -1;
      if (!YAML::convert<long>::decode(root["domain"], domain) || domain < 0 || domain > kMaxDomainId) {
        p.add("domain", "must be an integer 0.." + std::to_string(kMaxDomainId) + ", got '" +
                            root["domain"].as<std::string>() + "'");
      }
      plant.domain_id = static_cast<int>(domain);
    }
    if (!root["security"] || !root["security"].IsScalar() || root["security"].as<std::string>().empty()) {
      p.add("security", "missing: the PKI folder on every host (deploy/security/make-pki.sh), or 'off' for an open bus");
    } else {
      plant.security = root["security"].as<std::string>();
      if (plant.security != "off" && plant.security.front() != '/') {
        p.add("security", "'" + plant.security + "' must be an absolute path or 'off'");
      }
    }
    if (const YAML::Node ds = root["discovery_server"]) {
      DiscoveryServer server;
      if (!ds.IsMap() || !ds["host"]) {
        p.add("discovery_server", "must be a map with 'host' (and optionally 'port')");
      } else {
        check_keys(ds, {"host", "port"}, "discovery_server", p);
        server.host = ds["host"].as<std::string>();
        long port = server.port;
        if (ds["port"] && (!YAML::convert<long>::decode(ds["port"], port) || port < 1 || port > 65535)) {
          p.add("discovery_server.port", "must be 1..65535");
        }
        server.port = static_cast<int>(port);
        plant.discovery_server = server;
      }
    }
    const YAML::Node hosts = root["hosts"];
    if (!hosts || !hosts.IsSequence() || hosts.size() == 0) {
      p.add("hosts", "missing: a list of hosts with name, address and roles");
      return result;
    }
    for (std::size_t i = 0; i < hosts.size(); ++i) {
      PlantHost host;
      parse_host(hosts[i], "hosts[" + std::to_string(i) + "]", host, p);
      plant.hosts.push_back(host);
    }
    check_plant(plant, p);
  } catch (const YAML::Exception& e) {
    p.add("YAML", e.what());
  }
  return result;
}

PlantParseResult load_plant_description(const std::string& path) {
  if (!std::ifstream(path)) {
    PlantParseResult result;
    result.problems.push_back(path + ": cannot read the file");
    return result;
  }
  std::string text;
  try {
    text = config::read_yaml_file(path);  // at most kMaxYamlBytes (yaml_bounds.hpp)
  } catch (const config::ConfigError& e) {
    PlantParseResult result;
    result.problems.push_back(e.what());
    return result;
  }
  return parse_plant_description(text, path);
}

}  // namespace causal::plant
