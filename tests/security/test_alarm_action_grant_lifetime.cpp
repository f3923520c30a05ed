// A grant holds for the writer's life on alarm-recommender's alarm actions (acknowledge / shelve), as on its
// what-if requests. An operator identity (its grant names no partitions) matches the secured alarm-recommender and
// sends actions (taken and judged: the alarm ids are unknown, so refused as unknown_alarm); then it adds a group
// partition to its publisher with Publisher::set_qos. The recommender refuses every action of that writer from then
// on, whatever the group, before looking at the alarm: counted exactly (summary not_entitled, exit 4), answered
// "refused", alarmed once per group (HEALTH group_not_entitled naming the writer's participant). The attack is
// partition_switch.hpp's. Private loopback domain; about 15 s.
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

constexpr std::uint64_t kBefore = 4, kAfter = 3;  // actions per group before / after the partition change

causal_twin::AlarmAction action(const std::string& group, std::uint64_t n) {
  causal_twin::AlarmAction a;
  a.request_id("switcher-" + std::to_string(n));
  a.asset_group(group);
  a.alarm_id(group + "/1/feature_drift/1");
  a.action(causal_twin::ACKNOWLEDGE);
  a.user_name("mallory");
  a.time_ns(1'800'000'000'000'000'000LL);
  return a;
}

TEST(AlarmActionGrantLifetime, ASenderThatChangesItsPartitionsIsRefusedFromThenOn) {
  const int domain = causal::test::private_domain_id(64);
  const fs::path work = fresh_dir("alarm_action_grant_lifetime");
  const fs::path pki = make_plant_pki(work, domain);
  ServiceProcess recommender("alarm-recommender",
                             {ALARM_RECOMMENDER_BIN, "--domain", std::to_string(domain), "--security", pki.string(),
                              "--idle-exit", "6", "--max-runtime", "60"},  // idle: outlasts the attack's waits
                             (work / "recommender.log").string());
  PartitionSwitch<causal_twin::AlarmAction> plan{
      "operator", "action-switcher", {}, {"", causal::dds::group_partition("line-b")}, {}};
  std::uint64_t n = 0;
  for (std::uint64_t i = 0; i < kBefore; ++i) {
    for (const char* group : {"line-a", "line-b"}) plan.before.push_back(action(group, n++));
  }
  for (std::uint64_t i = 0; i < kAfter; ++i) {
    for (const char* group : {"line-a", "line-b"}) plan.after.push_back(action(group, n++));
  }
  const std::uint64_t sent = write_and_switch_partitions<causal_twin::AlarmActionPubSubType>(
      domain, pki, causal::dds::topics::kAlarmAction, causal::dds::profiles::kAlarmActionWriter, plan,
      [&] { return recommender.output(); });
  const auto code = recommender.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << recommender.output();
  const std::string log = recommender.output();
  for (const char* marker : {"summary topic=causal_twin/alarm_action ", "HEALTH RAISED"}) {
    const auto at = log.find(marker);
    if (at != std::string::npos) std::cout << "recommender: " << log.substr(at, log.find('\n', at) - at).substr(0, 200) << "\n";
  }
  EXPECT_EQ(sent, 2 * (kBefore + kAfter));
  EXPECT_EQ(*code, 4) << "refusals make the exit code 4:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm_action", "received"), 2 * (kBefore + kAfter)) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm_action", "not_entitled"), 2 * kAfter) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm_action", "applied"), 0u) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm_action_result", "sent"), 2 * (kBefore + kAfter)) << log;
  EXPECT_EQ(occurrences(log, ": unknown alarm id '"), 2 * kBefore) << "judged on the alarm before the change:\n" << log;
  EXPECT_EQ(occurrences(log, ": refused: the sender may not act on asset group"), 2 * kAfter) << log;
  EXPECT_NE(log.find("changed its partitions after discovery"), std::string::npos) << log;
  EXPECT_NE(log.find("of participant '" + plan.participant_name + "'"), std::string::npos) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED line-a/alarm_action/group_not_entitled/"), 1u) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED line-b/alarm_action/group_not_entitled/"), 1u) << log;
  fs::remove_all(work);
}

}  // namespace
