// causal-plant-profiles' output read back by Fast DDS's own XML parser (the truth: what the services get
// when they load the file with --transport): addresses, peers, transports, security and discovery as the
// plant file says, for every host.
#include "plant_description.hpp"
#include "plant_profile_xml.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

using eprosima::fastdds::dds::DomainParticipantFactory;
using eprosima::fastdds::dds::DomainParticipantQos;
using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::LocatorList_t;

const char* const kThreeHosts = R"(
domain: 84
security: off
hosts:
  - {name: sensors, address: 10.84.0.1, roles: [sensor]}
  - {name: analytics, address: 10.84.0.2, roles: [estimator 0/2, estimator 1/2]}
  - {name: operator, address: 10.84.0.3, roles: [recommender, recorder, web]}
)";

causal::plant::PlantDescription parse(const std::string& text) {
  const auto r = causal::plant::parse_plant_description(text, "test.yaml");
  EXPECT_TRUE(r.ok()) << (r.problems.empty() ? "" : r.problems.front());
  return r.plant;
}

// The participant profile `xml` defines, as Fast DDS parses it (a fresh profile manager every time: the
// profile name is the same in every generated file).
DomainParticipantQos parsed_qos(const std::string& xml, const std::string& profile = "causal_twin_participant") {
  eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
  DomainParticipantQos qos;
  auto* factory = DomainParticipantFactory::get_instance();
  EXPECT_EQ(factory->load_XML_profiles_string(xml.c_str(), xml.size()), ReturnCode_t::RETCODE_OK) << xml;
  EXPECT_EQ(factory->get_participant_qos_from_profile(profile, qos), ReturnCode_t::RETCODE_OK);
  return qos;
}

std::vector<std::string> addresses(const LocatorList_t& list) {
  std::vector<std::string> out;
  for (const auto& locator : list) out.push_back(IPLocator::toIPv4string(locator));
  return out;
}

std::string property(const DomainParticipantQos& qos, const std::string& name) {
  for (const auto& p : qos.properties().properties())
    if (p.name() == name) return p.value();
  return "(absent)";
}

struct Transports {
  std::shared_ptr<UDPv4TransportDescriptor> udp;
  int udp_count = 0;
  int shm_count = 0;
  int other_count = 0;
};

Transports transports(const DomainParticipantQos& qos) {
  Transports t;
  for (const auto& d : qos.transport().user_transports) {
    if (auto udp = std::dynamic_pointer_cast<UDPv4TransportDescriptor>(d)) {
      t.udp = udp;
      ++t.udp_count;
    } else if (std::dynamic_pointer_cast<SharedMemTransportDescriptor>(d)) {
      ++t.shm_count;
    } else {
      ++t.other_count;
    }
  }
  return t;
}

TEST(PlantProfileXml, EveryHostGetsItsAddressAndEveryHostAsPeer) {
  const auto plant = parse(kThreeHosts);
  const std::vector<std::string> all = {"10.84.0.1", "10.84.0.2", "10.84.0.3"};
  for (const auto& host : plant.hosts) {
    SCOPED_TRACE(host.name);
    const auto qos = parsed_qos(causal::plant::participant_profile_xml(plant, host, "test.yaml"));
    const auto& builtin = qos.wire_protocol().builtin;
    EXPECT_EQ(addresses(builtin.initialPeersList), all);
    EXPECT_EQ(addresses(builtin.metatrafficUnicastLocatorList), std::vector<std::string>{host.address});
    // No multicast: the explicit unicast metatraffic locator replaces Fast DDS's default multicast ones.
    EXPECT_TRUE(builtin.metatrafficMulticastLocatorList.empty());
    EXPECT_EQ(builtin.discovery_config.discoveryProtocol, eprosima::fastrtps::rtps::DiscoveryProtocol_t::SIMPLE);
    EXPECT_EQ(builtin.discovery_config.leaseDuration.seconds, 5);
    EXPECT_FALSE(qos.transport().use_builtin_transports);
    const Transports t = transports(qos);
    ASSERT_EQ(t.udp_count, 1);
    EXPECT_EQ(t.udp->interfaceWhiteList, std::vector<std::string>{host.address});
    // At most 3 services on one host + 4 spare participant ids.
    EXPECT_EQ(t.udp->maxInitialPeersRange, 7u);
    // No shared memory, also where services share a host (other users' processes stalled it).
    EXPECT_EQ(t.shm_count, 0);
    EXPECT_EQ(t.other_count, 0);
    EXPECT_EQ(property(qos, "causal_twin.security_dir"), "off");
  }
}

TEST(PlantProfileXml, SecurityFolderGoesToTheProperty) {
  const auto plant = parse(std::string(kThreeHosts).replace(std::string(kThreeHosts).find("off"), 3, "/srv/pki & co"));
  const auto qos = parsed_qos(causal::plant::participant_profile_xml(plant, plant.hosts[0], "a<b>.yaml"));
  EXPECT_EQ(property(qos, "causal_twin.security_dir"), "/srv/pki & co");
}

TEST(PlantProfileXml, DiscoveryServerReplacesPeerAnnouncements) {
  const auto plant = parse(std::string(kThreeHosts) + "discovery_server: {host: operator, port: 11900}\n");
  for (const auto& host : plant.hosts) {
    SCOPED_TRACE(host.name);
    const auto qos = parsed_qos(causal::plant::participant_profile_xml(plant, host, "test.yaml"));
    const auto& builtin = qos.wire_protocol().builtin;
    EXPECT_EQ(builtin.discovery_config.discoveryProtocol, eprosima::fastrtps::rtps::DiscoveryProtocol_t::CLIENT);
    ASSERT_EQ(builtin.discovery_config.m_DiscoveryServers.size(), 1u);
    const auto& server = builtin.discovery_config.m_DiscoveryServers.front();
    ASSERT_EQ(server.metatrafficUnicastLocatorList.size(), 1u);
    const auto& locator = *server.metatrafficUnicastLocatorList.begin();
    EXPECT_EQ(IPLocator::toIPv4string(locator), "10.84.0.3");
    EXPECT_EQ(locator.port, 11900u);
    EXPECT_TRUE(builtin.initialPeersList.empty());
    EXPECT_EQ(addresses(builtin.metatrafficUnicastLocatorList), std::vector<std::string>{host.address});
  }
}

TEST(PlantProfileXml, DiscoveryServerProfileListensOnThePlantAddressOnly) {
  EXPECT_EQ(causal::plant::discovery_server_profile_xml(parse(kThreeHosts), "test.yaml"), "");
  const auto plant = parse(std::string(kThreeHosts) + "discovery_server: {host: analytics, port: 11900}\n");
  const auto qos = parsed_qos(causal::plant::discovery_server_profile_xml(plant, "test.yaml"), "causal_twin_discovery_server");
  const auto& builtin = qos.wire_protocol().builtin;
  EXPECT_EQ(builtin.discovery_config.discoveryProtocol, eprosima::fastrtps::rtps::DiscoveryProtocol_t::SERVER);
  // The prefix of server id 0, which the clients' RemoteServer names.
  std::ostringstream prefix;
  prefix << qos.wire_protocol().prefix;
  EXPECT_EQ(prefix.str(), "44.53.00.5f.45.50.52.4f.53.49.4d.41");
  ASSERT_EQ(builtin.metatrafficUnicastLocatorList.size(), 1u);
  EXPECT_EQ(IPLocator::toIPv4string(*builtin.metatrafficUnicastLocatorList.begin()), "10.84.0.2");
  EXPECT_EQ(builtin.metatrafficUnicastLocatorList.begin()->port, 11900u);
  EXPECT_FALSE(qos.transport().use_builtin_transports);
  const Transports t = transports(qos);
  ASSERT_EQ(t.udp_count, 1);
  EXPECT_EQ(t.udp->interfaceWhiteList, std::vector<std::string>{"10.84.0.2"});
  EXPECT_EQ(t.shm_count + t.other_count, 0);
}

TEST(PlantProfileXml, CommandsStartEachRoleWithTheProfile) {
  const auto plant = parse(std::string(kThreeHosts) + "discovery_server: {host: operator}\n");
  const std::string tail = " --domain 84 --transport /etc/p.xml";
  const auto analytics = causal::plant::host_commands(plant, plant.hosts[1], "/etc/p.xml");
  ASSERT_EQ(analytics.size(), 2u);
  EXPECT_EQ(analytics[0], "causal-estimator" + tail + " --shard-index 0 --shard-count 2");
  EXPECT_EQ(analytics[1], "causal-estimator" + tail + " --shard-index 1 --shard-count 2");
  const auto sensors = causal::plant::host_commands(plant, plant.hosts[0], "/etc/p.xml");
  ASSERT_EQ(sensors.size(), 1u);
  EXPECT_EQ(sensors[0].rfind("sensor-replay" + tail + " --wait-for causal-estimator:2", 0), 0u) << sensors[0];
  const auto ops = causal::plant::host_commands(plant, plant.hosts[2], "/etc/p.xml");
  ASSERT_EQ(ops.size(), 4u);
  EXPECT_EQ(ops[0], "fast-discovery-server -x /etc/discovery-server.xml");
  EXPECT_EQ(ops[1], "alarm-recommender" + tail);
  EXPECT_EQ(ops[3], "twin-web" + tail + " --bind 10.84.0.3 --port 8080");
}

}  // namespace
