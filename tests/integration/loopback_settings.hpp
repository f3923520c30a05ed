// The settings of a test's own DDS participant: the shipped QoS and the loopback-only profile, the same files
// as every service the tests start, so that the test talks to them and to nothing outside this machine.
#pragma once

#include "causal/dds/participant.hpp"

#include <string>

namespace causal::test {

inline dds::DdsSettings loopback_settings(int domain_id, const std::string& participant_name) {
  dds::DdsSettings s;
  s.profile_files = {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml",
                     std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"};
  s.domain_id = domain_id;
  s.participant_name = participant_name;
  return s;
}

}  // namespace causal::test
