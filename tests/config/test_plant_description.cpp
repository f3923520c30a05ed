// causal-plant-profiles' plant description: the shipped example parses as written, and every kind of mistake
// is reported, all at once, naming the host or key (a plant engineer fixes the file in one pass).
#include "plant_description.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using causal::plant::parse_plant_description;
using causal::plant::RoleKind;

const std::string kValidHosts = R"(
hosts:
  - {name: a, address: 10.1.0.1, roles: [sensor]}
  - {name: b, address: 10.1.0.2, roles: [estimator]}
  - {name: c, address: 10.1.0.3, roles: [recommender, recorder]}
)";

std::string plant(const std::string& hosts, const std::string& head = "domain: 7\nsecurity: off\n") {
  return head + hosts;
}

// True when exactly one problem mentions every one of `words`.
bool reported(const std::vector<std::string>& problems, std::initializer_list<const char*> words) {
  int hits = 0;
  for (const auto& p : problems) {
    bool all = true;
    for (const char* w : words) all = all && p.find(w) != std::string::npos;
    hits += all ? 1 : 0;
  }
  return hits == 1;
}

std::string joined(const std::vector<std::string>& problems) {
  std::string out;
  for (const auto& p : problems) out += p + "\n";
  return out;
}

// Exactly these problems: as many as `each` lists, and every entry's words in exactly one of them.
void expect_problems(const std::vector<std::string>& problems,
                     std::initializer_list<std::initializer_list<const char*>> each) {
  EXPECT_EQ(problems.size(), each.size()) << joined(problems);
  for (const auto& words : each) EXPECT_TRUE(reported(problems, words)) << *words.begin() << "\n" << joined(problems);
}

TEST(PlantDescription, ShippedExampleParsesAsWritten) {
  const auto r = causal::plant::load_plant_description(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/plant/example-plant.yaml");
  ASSERT_TRUE(r.ok()) << joined(r.problems);
  EXPECT_EQ(r.plant.domain_id, 42);
  EXPECT_EQ(r.plant.security, "/etc/causal-twin/security");
  EXPECT_FALSE(r.plant.discovery_server.has_value());
  ASSERT_EQ(r.plant.hosts.size(), 3u);
  EXPECT_EQ(r.plant.hosts[0].name, "sensors");
  EXPECT_EQ(r.plant.hosts[0].address, "10.20.0.11");
  EXPECT_EQ(r.plant.hosts[0].interface, "eth1");
  ASSERT_EQ(r.plant.hosts[1].roles.size(), 2u);
  EXPECT_EQ(r.plant.hosts[1].roles[1].kind, RoleKind::Estimator);
  EXPECT_EQ(r.plant.hosts[1].roles[1].shard_index, 1);
  EXPECT_EQ(r.plant.hosts[1].roles[1].shard_count, 2);
  EXPECT_EQ(causal::plant::role_text(r.plant.hosts[1].roles[0]), "estimator 0/2");
  EXPECT_EQ(r.plant.hosts[2].roles.size(), 4u);
  EXPECT_EQ(causal::plant::max_participants_per_host(r.plant), 4);
}

TEST(PlantDescription, MinimalPlantIsValid) {
  const auto r = parse_plant_description(plant(kValidHosts), "p.yaml");
  EXPECT_TRUE(r.ok()) << joined(r.problems);
  EXPECT_EQ(r.plant.security, "off");
}

TEST(PlantDescription, Ipv4AddressSyntax) {
  using causal::plant::is_ipv4_address;
  EXPECT_TRUE(is_ipv4_address("10.20.0.11"));
  EXPECT_TRUE(is_ipv4_address("255.255.255.255"));
  EXPECT_FALSE(is_ipv4_address("10.20.0"));
  EXPECT_FALSE(is_ipv4_address("10.20.0.11.5"));
  EXPECT_FALSE(is_ipv4_address("10.256.0.1"));
  EXPECT_FALSE(is_ipv4_address("10.02.0.1"));
  EXPECT_FALSE(is_ipv4_address("10..0.1"));
  EXPECT_FALSE(is_ipv4_address("host.example"));
  EXPECT_FALSE(is_ipv4_address(" 10.0.0.1"));
}

TEST(PlantDescription, DuplicateHostNameAndAddress) {
  const auto r = parse_plant_description(plant(kValidHosts + "  - {name: a, address: 10.1.0.3, roles: [web]}\n"), "p.yaml");
  expect_problems(r.problems, {{"p.yaml", "duplicate host name 'a'"}, {"duplicate address 10.1.0.3"}});
}

TEST(PlantDescription, BadAddresses) {
  const auto r = parse_plant_description(plant(R"(
hosts:
  - {name: a, address: 10.1.0.300, roles: [sensor]}
  - {name: b, address: 127.0.0.1, roles: [estimator]}
  - {name: c, address: 239.255.0.1, roles: [recommender]}
  - {name: d, roles: [recorder]}
)"),
                                         "p.yaml");
  expect_problems(r.problems, {{"hosts[0] (a)", "'10.1.0.300' is not an IPv4 address"},
                               {"hosts[1] (b)", "loopback"},
                               {"hosts[2] (c)", "multicast"},
                               {"hosts[3] (d)", "missing 'address'"}});
}

TEST(PlantDescription, MissingAndUnknownRoles) {
  const auto r = parse_plant_description(plant(R"(
hosts:
  - {name: a, address: 10.1.0.1, roles: [sensor, sensor]}
  - {name: b, address: 10.1.0.2}
  - {name: c, address: 10.1.0.3, roles: [estimater, recorder 1/2]}
)"),
                                         "p.yaml");
  // Per host: a role twice, no roles, two unknown roles; for the plant: no estimator, no recommender.
  expect_problems(r.problems, {{"(a)", "role 'sensor' given twice"},
                               {"(b)", "missing 'roles'"},
                               {"(c)", "unknown role 'estimater'"},
                               {"(c)", "unknown role 'recorder 1/2'"},
                               {"no host has the role 'estimator'"},
                               {"no host has the role 'recommender'"}});
}

TEST(PlantDescription, EstimatorShardsMustBeCompleteAndConsistent) {
  const auto gap = parse_plant_description(plant(R"(
hosts:
  - {name: a, address: 10.1.0.1, roles: [sensor, recommender]}
  - {name: b, address: 10.1.0.2, roles: [estimator 0/3, estimator 2/3]}
  - {name: c, address: 10.1.0.3, roles: [estimator 2/3, estimator 3/3]}
)"),
                                           "p.yaml");
  // 3/3 is not a shard of 3; shard 1/3 is missing; shard 2/3 runs twice.
  expect_problems(gap.problems, {{"unknown role 'estimator 3/3'"},
                                 {"shard 1/3 is on no host"},
                                 {"shard 2/3 is on 2 hosts"}});

  const auto mixed = parse_plant_description(plant(R"(
hosts:
  - {name: a, address: 10.1.0.1, roles: [sensor, recommender, estimator]}
  - {name: b, address: 10.1.0.2, roles: [estimator 1/2]}
)"),
                                             "p.yaml");
  expect_problems(mixed.problems, {{"disagree on the shard count"}});
}

TEST(PlantDescription, TopLevelKeys) {
  const auto r = parse_plant_description(
      plant(kValidHosts, "domain: 233\nsecurity: etc/pki\ndiscovery_server: {host: z, port: 70000}\ntransport: udp\n"),
      "p.yaml");
  expect_problems(r.problems, {{"unknown key 'transport'"},
                               {"domain", "0..232", "'233'"},
                               {"security", "absolute path or 'off'"},
                               {"discovery_server.port", "1..65535"},
                               {"discovery_server.host", "'z' is not one of the hosts"}});

  const auto none = parse_plant_description("hosts: []\n", "p.yaml");
  EXPECT_EQ(none.problems.size(), 3u) << joined(none.problems);  // domain, security, hosts
  EXPECT_TRUE(reported(parse_plant_description("domain: [", "p.yaml").problems, {"p.yaml: YAML"}));
  EXPECT_TRUE(reported(causal::plant::load_plant_description("/nonexistent/plant.yaml").problems, {"cannot read"}));
}

}  // namespace

// A sensor host may name the asset groups its identity is granted (make-pki.sh --plant).
TEST(PlantDescription, SensorHostsNameTheirAssetGroups) {
  const auto ok = parse_plant_description(plant(R"(
hosts:
  - {name: a, address: 10.1.0.1, roles: [sensor], groups: [line-1.pump, line_2]}
  - {name: b, address: 10.1.0.2, roles: [estimator, recommender]}
)"), "plant.yaml");
  ASSERT_TRUE(ok.ok()) << joined(ok.problems);
  EXPECT_EQ(ok.plant.hosts[0].groups, (std::vector<std::string>{"line-1.pump", "line_2"}));
  EXPECT_EQ(causal::plant::sensor_identity(ok.plant.hosts[0]), "sensor-a");
  EXPECT_TRUE(ok.plant.hosts[1].groups.empty());
  const auto bad = parse_plant_description(plant(R"(
hosts:
  - {name: a, address: 10.1.0.1, roles: [sensor], groups: ["line*", ok]}
  - {name: b, address: 10.1.0.2, roles: [estimator, recommender], groups: [x]}
  - {name: c, address: 10.1.0.3, roles: [sensor], groups: []}
)"), "plant.yaml");
  EXPECT_TRUE(reported(bad.problems, {"hosts[0]", "asset group 'line*'"})) << joined(bad.problems);
  EXPECT_TRUE(reported(bad.problems, {"hosts[1]", "'groups' is for hosts with the role 'sensor'"})) << joined(bad.problems);
  EXPECT_TRUE(reported(bad.problems, {"hosts[2]", "'groups' must be a list"})) << joined(bad.problems);
}
