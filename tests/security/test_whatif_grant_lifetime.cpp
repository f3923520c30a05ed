// A grant holds for the writer's life on alarm-recommender's what-if requests too. An operator identity (its grant
// names no partitions: it may ask about every group) matches the secured alarm-recommender and asks its questions
// (answered); then it adds a group partition to its publisher with Publisher::set_qos, which Fast DDS 2.9 lets
// through with a log line. The recommender refuses every request of that writer from then on, whatever the group:
// counted exactly (summary not_entitled, exit 4), answered "refused", alarmed once per group (HEALTH
// group_not_entitled naming the writer's participant). The attack itself is shared with the estimator's test
// (partition_switch.hpp). Private loopback domain; about 15 s.
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

constexpr std::uint64_t kBefore = 6, kAfter = 5;  // requests per group before / after the partition change

causal_twin::WhatIfRequest request(const std::string& group, std::uint64_t n) {
  causal_twin::WhatIfRequest r;
  r.request_id("switcher-" + std::to_string(n));
  r.asset_group(group);
  r.intervene_channel(1);
  r.delta(0.5);
  r.sustained(true);
  return r;
}

TEST(WhatIfGrantLifetime, AnAskerThatChangesItsPartitionsIsRefusedFromThenOn) {
  const int domain = causal::test::private_domain_id(63);
  const fs::path work = fresh_dir("whatif_grant_lifetime");
  const fs::path pki = make_plant_pki(work, domain);
  ServiceProcess recommender("alarm-recommender",
                             {ALARM_RECOMMENDER_BIN, "--domain", std::to_string(domain), "--security", pki.string(),
                              // idle: the 3 s the attack waits around its change, and more (no factor writer
                              // keeps it up)
                              "--idle-exit", "6", "--max-runtime", "60"},
                             (work / "recommender.log").string());
  // The empty partition stays: the recommender's reader is in it, so the match (and the attack) goes on.
  PartitionSwitch<causal_twin::WhatIfRequest> plan{
      "operator", "whatif-switcher", {}, {"", causal::dds::group_partition("line-b")}, {}};
  std::uint64_t n = 0;
  for (std::uint64_t i = 0; i < kBefore; ++i) {
    for (const char* group : {"line-a", "line-b"}) plan.before.push_back(request(group, n++));
  }
  for (std::uint64_t i = 0; i < kAfter; ++i) {
    for (const char* group : {"line-a", "line-b"}) plan.after.push_back(request(group, n++));
  }
  const std::uint64_t sent = write_and_switch_partitions<causal_twin::WhatIfRequestPubSubType>(
      domain, pki, causal::dds::topics::kWhatIfRequest, causal::dds::profiles::kWhatIfWriter, plan,
      [&] { return recommender.output(); });
  const auto code = recommender.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << recommender.output();
  const std::string log = recommender.output();
  for (const char* marker : {"summary topic=causal_twin/whatif_request", "HEALTH RAISED"}) {
    const auto at = log.find(marker);
    if (at != std::string::npos) std::cout << "recommender: " << log.substr(at, log.find('\n', at) - at).substr(0, 200) << "\n";
  }
  EXPECT_EQ(sent, 2 * (kBefore + kAfter));
  EXPECT_EQ(*code, 4) << "refusals make the exit code 4:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/whatif_request", "received"), 2 * (kBefore + kAfter)) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/whatif_request", "not_entitled"), 2 * kAfter) << log;
  EXPECT_EQ(occurrences(log, "what-if switcher-"), 2 * kBefore) << "the requests before the change answered:\n" << log;
  EXPECT_NE(log.find("changed its partitions after discovery"), std::string::npos) << log;
  EXPECT_NE(log.find("of participant '" + plan.participant_name + "'"), std::string::npos) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED line-a/whatif/group_not_entitled/"), 1u) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED line-b/whatif/group_not_entitled/"), 1u) << log;
  fs::remove_all(work);
}

}  // namespace
