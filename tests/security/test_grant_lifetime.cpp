// A grant holds for the writer's life. A sensor identity granted line-a (make-pki.sh --plant) creates its
// condition_input writer in causal_twin/group/line-a, matches the secured causal-estimator and writes line-a
// inputs (processed); then it moves its publisher to other partitions with Publisher::set_qos. Fast DDS 2.9 keeps
// the match (it only logs "partition not found in rule"), and the estimator used to take the writer's new
// partitions from the discovery update. Now the writer is refused from the change on, for every group, its own
// included: counted exactly (not_entitled, exit 4) and alarmed (HEALTH group_not_entitled naming the writer's
// participant). Two ways: a switch to line-b, and adding the empty partition (which would let every group in).
// Private loopback domains; about 10 s per case.
#include "../fault/delivery_checks.hpp"
#include "causal/dds/topics.hpp"
#include "causal_twinPubSubTypes.h"
#include "partition_switch.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <iostream>

using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

constexpr std::uint64_t kBefore = 10, kAfter = 10;  // inputs written before / after the partition change
const std::string& kGranted = kGrantedGroup;

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
  PartitionSwitch<causal_twin::ConditionVector> plan{"sensor-line-a-sensors", "grant-switcher", {}, sw.partitions, {}};
  std::uint64_t snapshot = 0;
  for (std::uint64_t i = 0; i < kBefore; ++i, ++snapshot) plan.before.push_back(input(kGranted, snapshot));
  for (std::uint64_t i = 0; i < kAfter; ++i, ++snapshot) {
    for (const std::string& group : {sw.target, kGranted}) plan.after.push_back(input(group, snapshot));
  }
  const std::uint64_t sent = write_and_switch_partitions<causal_twin::ConditionVectorPubSubType>(
      domain, pki, causal::dds::topics::kConditionInput, causal::dds::profiles::kConditionInputWriter, plan,
      [&] { return estimator.output(); });
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
  EXPECT_NE(log.find("of participant '" + plan.participant_name + "'"), std::string::npos) << log;
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
