// Turns a validated plant description into what each host needs: one Fast DDS 2.9 XML profile (the
// participant profile the services load with --transport or $FASTRTPS_DEFAULT_PROFILES_FILE) and the
// command lines of the services the host runs.
#pragma once

#include "plant_description.hpp"

#include <string>
#include <vector>

namespace causal::plant {

// Participant ids a host may need beyond its roles: causal-ask runs, a hot standby, a test observer. Fast DDS
// announces to initial peers on the well-known ports of participant ids 0..maxInitialPeersRange-1 only.
constexpr int kSpareParticipantsPerHost = 4;

// The profile of `host`: UDPv4 bound (interfaceWhiteList) to the host's plant address, no multicast (explicit
// unicast metatraffic locator), built-in transports off, no shared memory (processes of other users on the
// host must not stall the services); discovery by unicast initial peers (every host of the plant, itself included, so services on
// one host find each other) or through the plant's discovery server; causal_twin.security_dir = the plant's
// security setting. `source` names the plant file in the header comment.
std::string participant_profile_xml(const PlantDescription& plant, const PlantHost& host, const std::string& source);

// The discovery server's own profile, for the plant's server host (`fast-discovery-server -x FILE`): a SERVER
// participant with the well-known prefix of server id 0 on the host's plant address and port, bound to that
// address like the clients. Its default settings would not do: it would listen on every interface and answer
// clients on its own host through 127.0.0.1, where they do not listen (they are bound to the plant address).
// Empty when the plant has no discovery server.
std::string discovery_server_profile_xml(const PlantDescription& plant, const std::string& source);

// The command lines that start the host's services (one per role; the discovery server first when it runs
// on this host). `profile_path` is where the profile will be installed on the host; the discovery server's
// profile goes next to it as discovery-server.xml.
std::vector<std::string> host_commands(const PlantDescription& plant, const PlantHost& host,
                                       const std::string& profile_path);

// Escapes &, <, >, " and ' for XML text and attribute values.
std::string xml_escape(const std::string& text);

}  // namespace causal::plant
