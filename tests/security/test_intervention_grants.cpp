// Grants on the closed loop's command topic (causal_twin/intervention) and operator identities limited to asset
// groups, on a secured bus with the shipped scripts' PKI:
// * A grant holds for the writer's life on the approved interventions too. An operator identity (its grant names no
//   partitions) matches the secured alarm-recommender (the outcome check) and sensor-sim's plant (the actuator) and
//   approves interventions for both simulated groups (taken by both); then it adds a group partition with
//   Publisher::set_qos (partition_switch.hpp). Both services refuse every approval of that writer from then on:
//   counted exactly (not_entitled), HEALTH group_not_entitled once per group naming the writer's participant, exit 4.
// * An operator identity issued with issue-identity.sh --groups sim-0000 sends what-if requests, alarm actions and
//   approvals for sim-0000 and sim-0001: those of sim-0000 are taken (answered, judged, approved, applied and
//   recorded), every one of sim-0001 is refused, counted and alarmed once per topic, and alarm-recommender,
//   sensor-sim and causal-recorder exit 4.
// Private loopback domains; about 15 s each.
#include "../fault/delivery_checks.hpp"
#include "causal/dds/topics.hpp"
#include "causal_twinPubSubTypes.h"
#include "operator_samples.hpp"
#include "partition_switch.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <regex>

using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

const std::string kGroup0 = "sim-0000", kGroup1 = "sim-0001";  // sensor-sim --groups 2

causal_twin::Intervention approval(const std::string& group, std::uint64_t n) {
  causal_twin::Intervention iv;
  iv.request_id(group + "/test/" + std::to_string(n));
  iv.asset_group(group);
  iv.channel(1);
  iv.change_percent(-10.0);
  iv.start_snapshot_index(100000 + 10 * n);  // far ahead of the plant: applied, never late, never overlapping
  iv.duration_snapshots(5);
  iv.target_channel(2);
  iv.approved_by("mallory");
  return iv;
}

// sensor-sim's plant: runs until terminated (snapshots far more than the test lasts).
std::vector<std::string> plant_args(int domain, const fs::path& pki) {
  return {SENSOR_SIM_BIN, "--domain", std::to_string(domain), "--security", pki.string(), "--security-identity",
          "sensor", "--plant", "lever", "--groups", "2", "--snapshots", "1000000", "--snapshot-rate", "20",
          "--wait-subscribers", "0"};
}

std::vector<std::string> recommender_args(int domain, const fs::path& pki) {
  // idle: outlasts the attack's waits (no factor writer keeps it up)
  return {ALARM_RECOMMENDER_BIN, "--domain", std::to_string(domain), "--security", pki.string(), "--idle-exit", "6",
          "--max-runtime", "60"};
}

// sensor-sim's summary line: "sensor-sim: sent snapshots=... interventions applied=N ... not_entitled=N".
std::optional<std::uint64_t> plant_count(const std::string& log, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(log, m, std::regex("sensor-sim: sent snapshots=.* " + key + "=([0-9]+)"))) return std::nullopt;
  return std::stoull(m[1].str());
}

void print_markers(const std::string& who, const std::string& log, const std::vector<std::string>& markers) {
  for (const auto& marker : markers) {
    for (auto at = log.find(marker); at != std::string::npos; at = log.find(marker, at + 1)) {
      std::cout << who << ": " << log.substr(at, log.find('\n', at) - at).substr(0, 160) << "\n";
    }
  }
}

TEST(InterventionGrantLifetime, AnApproverThatChangesItsPartitionsIsRefusedFromThenOn) {
  constexpr std::uint64_t kBefore = 3, kAfter = 2;  // approvals per group before / after the partition change
  const int domain = causal::test::private_domain_id(67);
  const fs::path work = fresh_dir("intervention_grant_lifetime");
  const fs::path pki = make_plant_pki(work, domain);
  ServiceProcess recommender("alarm-recommender", recommender_args(domain, pki), (work / "recommender.log").string());
  ServiceProcess plant("sensor-sim", plant_args(domain, pki), (work / "plant.log").string());
  PartitionSwitch<causal_twin::Intervention> plan{
      "operator", "approval-switcher", {}, {"", causal::dds::group_partition(kGroup1)}, {}, 2};
  std::uint64_t n = 0;
  for (std::uint64_t i = 0; i < kBefore; ++i) {
    for (const auto& group : {kGroup0, kGroup1}) plan.before.push_back(approval(group, n++));
  }
  for (std::uint64_t i = 0; i < kAfter; ++i) {
    for (const auto& group : {kGroup0, kGroup1}) plan.after.push_back(approval(group, n++));
  }
  const std::uint64_t sent = write_and_switch_partitions<causal_twin::InterventionPubSubType>(
      domain, pki, causal::dds::topics::kIntervention, causal::dds::profiles::kInterventionWriter, plan,
      [&] { return recommender.output() + plant.output(); });
  const int plant_code = plant.terminate();
  const auto code = recommender.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << recommender.output();
  const std::string log = recommender.output(), plant_log = plant.output();
  print_markers("recommender", log, {"summary topic=causal_twin/intervention ", "HEALTH RAISED"});
  print_markers("sensor-sim", plant_log, {"sensor-sim: sent", "HEALTH RAISED"});
  EXPECT_EQ(sent, 2 * (kBefore + kAfter));
  EXPECT_EQ(*code, 4) << "refusals make the exit code 4:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/intervention", "approved"), 2 * kBefore) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/intervention", "not_entitled"), 2 * kAfter) << log;
  EXPECT_EQ(plant_code, 4) << plant_log;
  EXPECT_EQ(plant_count(plant_log, "applied"), 2 * kBefore) << plant_log;
  EXPECT_EQ(plant_count(plant_log, "not_entitled"), 2 * kAfter) << plant_log;
  EXPECT_EQ(occurrences(plant_log, "HEALTH alarms of refused interventions are in this log only"), 1u)
      << "a sensor identity may not publish alarms:\n" << plant_log;
  for (const std::string* l : {&log, &plant_log}) {
    EXPECT_NE(l->find("changed its partitions after discovery"), std::string::npos) << *l;
    EXPECT_NE(l->find("of participant '" + plan.participant_name + "'"), std::string::npos) << *l;
    for (const auto& group : {kGroup0, kGroup1}) {
      EXPECT_EQ(occurrences(*l, "HEALTH RAISED " + group + "/intervention/group_not_entitled/"), 1u) << *l;
    }
  }
  fs::remove_all(work);
}

// Writes `count` samples of each group on `topic` once `readers` services matched; returns those written.
template <typename PubSubType, typename Make>
std::uint64_t write_each_group(causal::dds::Participant& p, const char* topic, const char* profile,
                               std::size_t readers, std::uint64_t count, const Make& make) {
  causal::dds::TypedWriter<PubSubType> w(p, topic, profile);
  const std::atomic<bool> never{false};
  if (!w.wait_for_readers(readers, std::chrono::seconds(30), never)) {
    ADD_FAILURE() << topic << ": the services never matched the group-limited writer";
    return 0;
  }
  std::uint64_t sent = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    for (const auto& group : {kGroup0, kGroup1}) {
      auto sample = make(group, sent);
      if (w.write(sample, never) == causal::dds::WriteResult::Ok) ++sent;
    }
  }
  EXPECT_TRUE(w.wait_for_acknowledgments(std::chrono::seconds(10))) << topic;
  return sent;
}

TEST(OperatorGroupGrants, AnOperatorLimitedToOneGroupIsRefusedEveryOther) {
  constexpr std::uint64_t kEach = 3;  // samples per group and topic
  const int domain = causal::test::private_domain_id(68);
  const fs::path work = fresh_dir("operator_group_grants");
  const fs::path pki = make_plant_pki(work, domain);
  run(script("issue-identity.sh") + " '" + pki.string() + "' operator-line-0 operator --groups " + kGroup0);
  const std::string grant = read_text(pki / "operator-line-0" / "permissions.xml");
  EXPECT_NE(grant.find("<partition>causal_twin/group/" + kGroup0 + "</partition>"), std::string::npos) << grant;
  ServiceProcess recommender("alarm-recommender", recommender_args(domain, pki), (work / "recommender.log").string());
  ServiceProcess plant("sensor-sim", plant_args(domain, pki), (work / "plant.log").string());
  ServiceProcess recorder("causal-recorder",
                          {CAUSAL_RECORDER_BIN, "--domain", std::to_string(domain), "--security", pki.string(), "--out",
                           (work / "rec").string(), "--idle-exit", "6", "--max-runtime", "60"},
                          (work / "recorder.log").string());
  std::uint64_t questions = 0, actions = 0, approvals = 0;
  {
    causal::dds::DdsSettings s = causal::test::loopback_settings(domain, "limited-operator");
    s.security_dir = pki.string();
    s.security_identity = "operator-line-0";
    causal::dds::Participant p(s);
    namespace t = causal::dds::topics;
    namespace pr = causal::dds::profiles;
    questions = write_each_group<causal_twin::WhatIfRequestPubSubType>(p, t::kWhatIfRequest, pr::kWhatIfWriter, 1,
                                                                       kEach, whatif_questions("limited-"));
    actions = write_each_group<causal_twin::AlarmActionPubSubType>(p, t::kAlarmAction, pr::kAlarmActionWriter, 1,
                                                                   kEach, acknowledgements("limited-", "olivia"));
    approvals = write_each_group<causal_twin::InterventionPubSubType>(p, t::kIntervention, pr::kInterventionWriter, 3,
                                                                      kEach, approval);
    std::this_thread::sleep_for(std::chrono::seconds(1));  // taken before the plant stops
  }
  const int plant_code = plant.terminate();
  const auto code = recommender.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << recommender.output();
  const auto recorder_code = recorder.wait(std::chrono::seconds(60));
  ASSERT_TRUE(recorder_code.has_value()) << recorder.output();
  const std::string log = recommender.output(), plant_log = plant.output(), recorder_log = recorder.output();
  print_markers("recommender", log, {"summary topic=causal_twin/whatif_request", "summary topic=causal_twin/alarm_action ",
                                     "summary topic=causal_twin/intervention ", "HEALTH RAISED"});
  print_markers("sensor-sim", plant_log, {"sensor-sim: sent", "HEALTH RAISED"});
  print_markers("recorder", recorder_log, {"interventions: received", "HEALTH RAISED"});
  EXPECT_EQ(questions, 2 * kEach);
  EXPECT_EQ(actions, 2 * kEach);
  EXPECT_EQ(approvals, 2 * kEach);
  EXPECT_EQ(*code, 4) << "refusals make the exit code 4:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/whatif_request", "received"), 2 * kEach) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/whatif_request", "not_entitled"), kEach) << log;
  EXPECT_EQ(occurrences(log, "on '" + kGroup0 + "': "), kEach) << "sim-0000's questions answered:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm_action", "received"), 2 * kEach) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm_action", "not_entitled"), kEach) << log;
  EXPECT_EQ(occurrences(log, ": unknown alarm id '"), kEach) << "sim-0000's actions judged:\n" << log;
  EXPECT_EQ(summary_count(log, "causal_twin/intervention", "approved"), kEach) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/intervention", "not_entitled"), kEach) << log;
  EXPECT_EQ(plant_code, 4) << plant_log;
  EXPECT_EQ(plant_count(plant_log, "applied"), kEach) << plant_log;
  EXPECT_EQ(plant_count(plant_log, "not_entitled"), kEach) << plant_log;
  EXPECT_EQ(*recorder_code, 4) << recorder_log;
  EXPECT_NE(recorder_log.find("interventions: received " + std::to_string(2 * kEach) + ", written " +
                              std::to_string(kEach) + ", duplicates 0, refused " + std::to_string(kEach)),
            std::string::npos) << recorder_log;
  EXPECT_EQ(occurrences(read_text(work / "rec" / "interventions.csv"), "\n"), kEach + 1) << "header and sim-0000's";
  const std::string why = "may write only its partitions [causal_twin/group/" + kGroup0 + "]";
  for (const std::string* l : {&log, &plant_log, &recorder_log}) {
    EXPECT_NE(l->find(why), std::string::npos) << *l;
    EXPECT_NE(l->find("of participant 'limited-operator'"), std::string::npos) << *l;
    EXPECT_EQ(occurrences(*l, "HEALTH RAISED " + kGroup0 + "/"), 0u) << *l;
    EXPECT_EQ(occurrences(*l, "HEALTH RAISED " + kGroup1 + "/intervention/group_not_entitled/"), 1u) << *l;
  }
  for (const char* part : {"whatif", "alarm_action"}) {
    EXPECT_EQ(occurrences(log, "HEALTH RAISED " + kGroup1 + "/" + part + "/group_not_entitled/"), 1u) << log;
  }
  fs::remove_all(work);
}

}  // namespace
