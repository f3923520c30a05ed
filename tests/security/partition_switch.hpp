// The partition-switch attack on a secured service, shared by the tests of every service that reads input from
// outside identities (causal-estimator's inputs, alarm-recommender's what-if requests, alarm actions and approved
// interventions, sensor-sim's approved interventions): a granted writer matches
// the service and writes samples its grant allows, then moves its publisher to other partitions with
// Publisher::set_qos (Fast DDS 2.9 keeps the match and only logs "partition not found in rule") and writes more.
// The service must refuse the writer from the change on, for every group (dds/writer_grant_check.hpp).
#pragma once

#include "causal/dds/group_partitions.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "loopback_settings.hpp"
#include "pki_fixture.hpp"

#include <fastdds/dds/publisher/Publisher.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace causal::test::security {

// The group make_plant_pki grants its sensor host "line-a-sensors" (identity "sensor-line-a-sensors").
inline const std::string kGrantedGroup = "line-a";

// A PKI of every role plus one sensor identity granted only kGrantedGroup (make-pki.sh --plant).
inline fs::path make_plant_pki(const fs::path& work, int domain) {
  const fs::path plant = work / "plant.yaml";
  std::ofstream(plant) << "domain: " << domain << "\nsecurity: /etc/causal-twin/security\n"
                       << "hosts:\n"
                       << "  - {name: line-a-sensors, address: 10.20.0.11, roles: [sensor], groups: ["
                       << kGrantedGroup << "]}\n"
                       << "  - {name: analytics, address: 10.20.0.12, roles: [estimator, recommender]}\n";
  const fs::path pki = work / "pki";
  run("CAUSAL_PLANT_PROFILES='" + std::string(CAUSAL_PLANT_PROFILES_BIN) + "' " + script("make-pki.sh") + " '" +
      pki.string() + "' --plant '" + plant.string() + "'");
  return pki;
}

inline std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The attacker's plan: identity and participant name, the samples before the change (all allowed), the
// partitions after it, and the samples after it (all to be refused).
template <typename Sample>
struct PartitionSwitch {
  std::string identity;          // in the PKI folder
  std::string participant_name;  // what the service's HEALTH alarm must name
  std::vector<Sample> before;
  std::vector<std::string> partitions;
  std::vector<Sample> after;
  std::size_t readers = 1;  // the services reading the topic (each must match before the attack starts)
};

// Runs the plan against a service already started on `domain` (its output for failure messages from
// `service_output`). Returns the number of samples written (each accepted by the writer).
template <typename PubSubType, typename Sample, typename Output>
std::uint64_t write_and_switch_partitions(int domain, const fs::path& pki, const char* topic, const char* profile,
                                          const PartitionSwitch<Sample>& plan, const Output& service_output) {
  causal::dds::DdsSettings s = causal::test::loopback_settings(domain, plan.participant_name);
  s.security_dir = pki.string();
  s.security_identity = plan.identity;
  causal::dds::Participant p(s);
  causal::dds::TypedWriter<PubSubType> w(p, topic, profile);
  const std::atomic<bool> never{false};
  std::uint64_t sent = 0;
  if (!w.wait_for_readers(plan.readers, std::chrono::seconds(30), never)) {
    ADD_FAILURE() << "the service never matched:\n" << service_output();
    return sent;
  }
  for (Sample v : plan.before) {
    if (w.write(v, never) == causal::dds::WriteResult::Ok) ++sent;
  }
  // Samples are judged when the service takes them: let it take these before the change is announced.
  EXPECT_EQ(p.publisher()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(10, 0)),
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  eprosima::fastdds::dds::PublisherQos qos = p.publisher()->get_qos();
  qos.partition().clear();
  for (const auto& name : plan.partitions) qos.partition().push_back(name.c_str());
  EXPECT_EQ(p.publisher()->set_qos(qos), eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  // The change reaches the service by discovery (its own channel): give it time to arrive first, as an attacker
  // would (samples written in between are judged by the first partitions).
  std::this_thread::sleep_for(std::chrono::seconds(2));
  EXPECT_EQ(w.matched_readers(), plan.readers) << "Fast DDS 2.9 keeps the match after the change";
  for (Sample v : plan.after) {
    if (w.write(v, never) == causal::dds::WriteResult::Ok) ++sent;
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));  // reliable delivery of the last ones
  return sent;
}

}  // namespace causal::test::security
