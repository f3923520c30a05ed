// causal-plant-profiles: from a plant description (hosts, addresses, services) to one Fast DDS profile per
// host, so a multi-host deployment is configuration only: copy <host>.xml to the host and start its services
// with --transport pointing at it (or $FASTRTPS_DEFAULT_PROFILES_FILE). No DDS here: the tool writes text.
#include "plant_description.hpp"
#include "plant_profile_xml.hpp"

#include <causal/config/cli_conventions.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace {

constexpr int kExitInvalid = 2;  // invalid plant description (as invalid configuration in every service)
constexpr int kExitOutput = 1;   // cannot write the output

const char* const kHelpFooter = R"(
Plant file (YAML; every problem is reported at once, each naming its host or key)
  domain: 42                               # DDS domain id of the plant, 0..232
  security: /etc/causal-twin/security      # PKI folder on every host (make-pki.sh), or off (open bus)
  discovery_server: {host: ops, port: 11811}   # optional: Fast DDS discovery server instead of peers lists
  hosts:
    - {name: sensors, address: 10.20.0.11, interface: eth1, roles: [sensor], groups: [line1-pump, line1-fan]}
    - {name: analytics, address: 10.20.0.12, roles: [estimator 0/2, estimator 1/2]}
    - {name: ops, address: 10.20.0.13, roles: [recommender, recorder, web, operator]}
  Roles: sensor, estimator (or estimator K/N: shard K of N), recommender, recorder, web, operator.
  groups (sensor hosts, optional): the asset groups their sensors may write; make-pki.sh --plant issues the
  identity sensor-<host> granted only those, and the estimator refuses (and counts) any other group from it.

Output (in --out): <host>.xml, the host's participant profile, and <host>.commands, the command lines of
its services; with a discovery server, also <host>.discovery-server.xml for its host (the server's own
profile). Copy them to the host (the profile to --installed-as, default /etc/causal-twin/plant.xml; the server's
profile next to it as discovery-server.xml).
Exit codes: 0 written, 2 invalid plant file (problems on stderr), 1 cannot write.
)";

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"causal-plant-profiles: one Fast DDS profile per host from a plant description"};
  std::string plant_file, out_dir = ".", installed_as = "/etc/causal-twin/plant.xml";
  bool check_only = false;
  app.add_option("plant", plant_file, "plant description (YAML), e.g. deploy/plant/example-plant.yaml")->required();
  app.add_option("--out", out_dir, "folder for <host>.xml and <host>.commands")->capture_default_str();
  app.add_option("--installed-as", installed_as, "path of the profile on each host, used in the commands")
      ->capture_default_str();
  app.add_flag("--check", check_only, "validate the plant file only; write nothing");
  bool identities = false;
  app.add_flag("--identities", identities,
               "print the sensor identities the plant names, one line each: NAME sensor GROUP,GROUP,... "
               "(read by deploy/security/make-pki.sh --plant); write nothing");
  app.footer(kHelpFooter);
  causal::config::add_version_flag(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? causal::config::kExitOk : causal::config::kExitUsage;  // a usage error (never CLI11's own codes)
  }

  const auto parsed = causal::plant::load_plant_description(plant_file);
  if (!parsed.ok()) {
    for (const auto& problem : parsed.problems) std::cerr << problem << "\n";
    std::cerr << "causal-plant-profiles: " << parsed.problems.size() << " problem(s); nothing written\n";
    return kExitInvalid;
  }
  const auto& plant = parsed.plant;
  if (identities) {
    for (const auto& host : plant.hosts) {
      if (host.groups.empty()) continue;
      std::string groups;
      for (const auto& g : host.groups) groups += (groups.empty() ? "" : ",") + g;
      std::cout << causal::plant::sensor_identity(host) << " sensor " << groups << "\n";
    }
    return 0;
  }
  std::cout << "plant " << plant_file << ": " << plant.hosts.size() << " hosts, domain " << plant.domain_id
            << ", security " << (plant.security == "off" ? "OFF (open bus)" : plant.security) << ", discovery "
            << (plant.discovery_server ? "server on " + plant.discovery_server->host : std::string("unicast peers"))
            << "\n";
  if (check_only) return 0;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  for (const auto& host : plant.hosts) {
    const std::string base = (std::filesystem::path(out_dir) / host.name).string();
    std::ofstream xml(base + ".xml"), commands(base + ".commands");
    xml << causal::plant::participant_profile_xml(plant, host, plant_file);
    std::cout << "\n" << base << ".xml  (copy to " << host.name << ":" << installed_as << ")\n";
    for (const auto& line : causal::plant::host_commands(plant, host, installed_as)) {
      commands << line << "\n";
      std::cout << "  " << line << "\n";
    }
    if (plant.discovery_server && plant.discovery_server->host == host.name) {
      std::ofstream server(base + ".discovery-server.xml");
      server << causal::plant::discovery_server_profile_xml(plant, plant_file);
      std::cout << base << ".discovery-server.xml  (copy next to it as discovery-server.xml)\n";
      if (!server.flush()) {
        std::cerr << "causal-plant-profiles: cannot write " << base << ".discovery-server.xml\n";
        return kExitOutput;
      }
    }
    if (!xml.flush() || !commands.flush()) {
      std::cerr << "causal-plant-profiles: cannot write " << base << ".xml/.commands\n";
      return kExitOutput;
    }
  }
  return 0;
}
