// The partition-switch attack (partition_switch.hpp) on a secured alarm-recommender, shared by the tests of its
// operator inputs (what-if requests, alarm actions): an operator identity (its grant names no partitions: every
// group) sends `before` samples per group (line-a, line-b), adds line-b's partition to its publisher, and sends
// `after` more per group. The recommender must refuse every sample of that writer from the change on, whatever the
// group: counted exactly (summary not_entitled, exit 4) and alarmed once per group (HEALTH group_not_entitled
// naming the writer's participant).
#pragma once

#include "../fault/delivery_checks.hpp"
#include "partition_switch.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <iostream>
#include <optional>
#include <string>

namespace causal::test::security {

struct RecommenderSwitch {
  std::string work_name;    // the test's folder (fresh_dir)
  int domain_offset = 0;    // private_domain_id's argument
  const char* topic = "";   // e.g. causal::dds::topics::kWhatIfRequest
  const char* profile = "";
  std::string participant;  // the attacker's participant name
  std::uint64_t before = 0, after = 0;  // samples per group before / after the change
};

struct RecommenderSwitchResult {
  std::uint64_t sent = 0;   // samples the attacker wrote (each accepted by its writer)
  std::optional<int> code;  // alarm-recommender's exit code; nullopt: it did not end in time
  std::string log;
};

// Runs the attack; make(group, n) builds the n-th sample (n from 0, alternating line-a and line-b).
template <typename PubSubType, typename Make>
RecommenderSwitchResult switch_against_recommender(const RecommenderSwitch& a, Make make) {
  const int domain = causal::test::private_domain_id(a.domain_offset);
  const fs::path work = fresh_dir(a.work_name);
  const fs::path pki = make_plant_pki(work, domain);
  causal::test::ServiceProcess recommender(
      "alarm-recommender",
      {ALARM_RECOMMENDER_BIN, "--domain", std::to_string(domain), "--security", pki.string(), "--idle-exit", "6",
       "--max-runtime", "60"},  // idle: the 3 s the attack waits around its change, and more
      (work / "recommender.log").string());
  // The empty partition stays: the recommender's reader is in it, so the match (and the attack) goes on.
  PartitionSwitch<decltype(make(std::string(), std::uint64_t{0}))> plan{
      "operator", a.participant, {}, {"", causal::dds::group_partition("line-b")}, {}};
  std::uint64_t n = 0;
  for (std::uint64_t i = 0; i < a.before; ++i) {
    for (const char* group : {"line-a", "line-b"}) plan.before.push_back(make(group, n++));
  }
  for (std::uint64_t i = 0; i < a.after; ++i) {
    for (const char* group : {"line-a", "line-b"}) plan.after.push_back(make(group, n++));
  }
  RecommenderSwitchResult r;
  r.sent = write_and_switch_partitions<PubSubType>(domain, pki, a.topic, a.profile, plan,
                                                   [&] { return recommender.output(); });
  r.code = recommender.wait(std::chrono::seconds(60));
  r.log = recommender.output();
  for (const std::string& marker : {"summary topic=" + std::string(a.topic) + " ", std::string("HEALTH RAISED")}) {
    const auto at = r.log.find(marker);
    if (at != std::string::npos) {
      std::cout << "recommender: " << r.log.substr(at, r.log.find('\n', at) - at).substr(0, 200) << "\n";
    }
  }
  if (r.code) fs::remove_all(work);
  return r;
}

// What every such attack must give: every sample written and received, exactly the `after` ones refused (exit 4),
// the change logged naming the participant, one HEALTH alarm per group of kind `health_kind`.
inline void expect_refused_from_the_change_on(const RecommenderSwitch& a, const RecommenderSwitchResult& r,
                                              const std::string& health_kind) {
  using causal::test::delivery::summary_count;
  ASSERT_TRUE(r.code.has_value()) << r.log;
  EXPECT_EQ(r.sent, 2 * (a.before + a.after));
  EXPECT_EQ(*r.code, 4) << "refusals make the exit code 4:\n" << r.log;
  EXPECT_EQ(summary_count(r.log, a.topic, "received"), 2 * (a.before + a.after)) << r.log;
  EXPECT_EQ(summary_count(r.log, a.topic, "not_entitled"), 2 * a.after) << r.log;
  EXPECT_NE(r.log.find("changed its partitions after discovery"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("of participant '" + a.participant + "'"), std::string::npos) << r.log;
  for (const char* group : {"line-a", "line-b"}) {
    EXPECT_EQ(occurrences(r.log, "HEALTH RAISED " + std::string(group) + "/" + health_kind + "/group_not_entitled/"), 1u)
        << r.log;
  }
}

}  // namespace causal::test::security
