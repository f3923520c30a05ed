// A grant holds for the writer's life. A sensor identity granted line-a (make-pki.sh --plant) creates its
// condition_input writer in causal_twin/group/line-a, matches the secured causal-estimator and writes line-a
// inputs (processed); then it moves its publisher to other partitions with Publisher::set_qos. Fast DDS 2.9 keeps
// the match (it only logs "partition not found in rule"), and the estimator used to take the writer's new
// partitions from the discovery update. Now the writer is refused from the change on, for every group, its own
// included: counted exactly (not_entitled, exit 4) and alarmed (HEALTH group_not_entitled naming the writer's
// participant). Two ways: a switch to line-b, and adding the empty partition (which would let every group in).
// Private loopback domains; about 10 s per case.
#include "../fault/delivery_checks.hpp"
#include "causal/dds/group_partitions.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"
#include "loopback_settings.hpp"
#include "pki_fixture.hpp"
#include "process_runner.hpp"

#include <fastdds/dds/publisher/Publisher.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <iostream>
#include <thread>

using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

constexpr std::uint64_t kBefore = 10, kAfter = 10;  // inputs written before / after the partition change
const std::string kGranted = "line-a";

fs::path make_plant_pki(const fs::path& work, int domain) {
  const fs::path plant = work / "plant.yaml";
  std::ofstream(plant) << "domain: " << domain << "\nsecurity: /etc/causal-twin/security\n"
                       << "hosts:\n"
                       << "  - {name: line-a-sensors, address: 10.20.0.11, roles: [sensor], groups: [" << kGranted
                       << "]}\n"
                       << "  - {name: analytics, address: 10.20.0.12, roles: [estimator, recommender]}\n";
  const fs::path pki = work / "pki";
  run("CAUSAL_PLANT_PROFILES='" + std::string(CAUSAL_PLANT_PROFILES_BIN) + "' " + script("make-pki.sh") + " '" +
      pki.string() + "' --plant '" + plant.string() + "'");
  return pki;
}

causal_twin::ConditionVector input(const std::string& group, std::uint64_t snapshot) {
  causal_twin::ConditionVector v;
  v.asset_group(group);
  v.feature("meanabs");
  v.snapshot_index(snapshot);
  v.time_ns(1700000000000000000LL + static_cast<std::int64_t>(snapshot) * 600000000000LL);
  v.channel_names({"b1", "b2", "b3", "b4"});
  v.values({0.1 + 0.001 * static_cast<double>(snapshot), 0.2, 0.3, 0.4});
  return v;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

struct Switch {
  const char* name;
  std::vector<std::string> partitions;  // the publisher's partitions after the change
  std::string target;                   // the group it then writes besides its own
};

class GrantLifetime : public ::testing::TestWithParam<Switch> {};

TEST_P(GrantLifetime, AWriterThatChangesItsPartitionsIsRefusedFromThenOn) {
  const Switch& sw = GetParam();
  const int domain = causal::test::private_domain_id(sw.target == "line-b" ? 61 : 62);
  const fs::path work = fresh_dir(std::string("grant_lifetime_") + sw.name);
  const fs::path pki = make_plant_pki(work, domain);
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", std::to_string(domain), "--security", pki.string(),
                            "--idle-exit", "3", "--max-runtime", "60"},
                           (work / "estimator.log").string());
  const std::string writer_name = "grant-switcher";
  std::uint64_t sent = 0;
  {
    causal::dds::DdsSettings s = causal::test::loopback_settings(domain, writer_name);
    s.security_dir = pki.string();
    s.security_identity = "sensor-line-a-sensors";
    causal::dds::Participant p(s);
    causal::dds::TypedWriter<causal_twin::ConditionVectorPubSubType> w(p, causal::dds::topics::kConditionInput,
                                                                        causal::dds::profiles::kConditionInputWriter);
    const std::atomic<bool> never{false};
    ASSERT_TRUE(w.wait_for_readers(1, std::chrono::seconds(30), never)) << estimator.output();
    std::uint64_t snapshot = 0;
    for (std::uint64_t i = 0; i < kBefore; ++i, ++snapshot) {
      auto v = input(kGranted, snapshot);
      ASSERT_EQ(w.write(v, never), causal::dds::WriteResult::Ok);
      ++sent;
    }
    // Inputs are judged when the estimator takes them: let it take these before the change is announced.
    ASSERT_EQ(p.publisher()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(10, 0)),
              eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
    std::this_thread::sleep_for(std::chrono::seconds(1));
    eprosima::fastdds::dds::PublisherQos qos = p.publisher()->get_qos();
    qos.partition().clear();
    for (const auto& name : sw.partitions) qos.partition().push_back(name.c_str());
    ASSERT_EQ(p.publisher()->set_qos(qos), eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
    // The change reaches the estimator by discovery (its own channel): give it time to arrive first, as an
    // attacker would (inputs written in between are judged by the first partitions: only line-a).
    std::this_thread::sleep_for(std::chrono::seconds(2));
    EXPECT_EQ(w.matched_readers(), 1u) << "Fast DDS 2.9 keeps the match after the change";
    for (std::uint64_t i = 0; i < kAfter; ++i, ++snapshot) {
      for (const std::string& group : {sw.target, kGranted}) {
        auto v = input(group, snapshot);
        if (w.write(v, never) == causal::dds::WriteResult::Ok) ++sent;
      }
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));  // reliable delivery of the last ones
  }
  const auto code = estimator.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << estimator.output();
  const std::string log = estimator.output();
  for (const char* marker : {"summary topic=causal_twin/condition_input", "summary not_processed", "HEALTH RAISED"}) {
    const auto at = log.find(marker);
    if (at != std::string::npos) std::cout << "estimator: " << log.substr(at, log.find('\n', at) - at).substr(0, 200) << "\n";
  }
  EXPECT_EQ(sent, kBefore + 2 * kAfter);
  EXPECT_EQ(*code, 4) << "refusals make the exit code 4:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/condition_input", "received"), kBefore + 2 * kAfter) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/condition_input", "not_entitled"), 2 * kAfter) << log;
  EXPECT_NE(log.find("changed its partitions after discovery"), std::string::npos) << log;
  EXPECT_NE(log.find("of participant '" + writer_name + "'"), std::string::npos) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED " + sw.target + "/input/group_not_entitled/"), 1u) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED " + kGranted + "/input/group_not_entitled/"), 1u) << log;
  fs::remove_all(work);
}

INSTANTIATE_TEST_SUITE_P(
    Switches, GrantLifetime,
    ::testing::Values(Switch{"to_another_group", {causal::dds::group_partition("line-b")}, "line-b"},
                      Switch{"adding_the_empty_partition", {causal::dds::group_partition(kGranted), ""}, "line-c"}),
    [](const auto& test) { return std::string(test.param.name); });

}  // namespace
