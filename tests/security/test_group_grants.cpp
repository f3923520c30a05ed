// Authorisation per asset group. A plant file names the asset groups of a sensor host;
// make-pki.sh --plant issues that host's identity granted only those (DDS partitions causal_twin/group/<group>).
// With a valid certificate of that identity:
// * Fast DDS refuses a writer that announces another group's partition (its own access control, locally);
// * two real sensor-replay processes publish, one its granted group, one another group: the secured
//   causal-estimator processes every sample of the granted group and refuses every sample of the other,
//   counted exactly (summary, exit code 4) and alarmed once (HEALTH group_not_entitled).
// And the HEALTH alarm 14 days before a service's own certificate expires: an estimator with a certificate
// valid for 10 days raises it once at its first input; the 825-day one of the run above raises none.
// Fixed loopback domains 51 and 52 (tests/security/CMakeLists.txt); about 15 s.
#include "../fault/delivery_checks.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal_twinPubSubTypes.h"
#include "loopback_settings.hpp"
#include "pki_fixture.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iostream>

using causal::test::expect_exit_zero;
using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

constexpr int kDomain = 51;
constexpr std::uint64_t kSnapshots = 40;  // per sensor-replay
const std::string kGranted = "line-a", kOther = "line-b";

std::string feature_table() {
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
}

// A plant whose sensor host names one asset group; make-pki.sh reads it through causal-plant-profiles.
fs::path make_plant_pki(const fs::path& work) {
  const fs::path plant = work / "plant.yaml";
  std::ofstream(plant) << "domain: " << kDomain << "\nsecurity: /etc/causal-twin/security\n"
                       << "hosts:\n"
                       << "  - {name: line-a-sensors, address: 10.20.0.11, roles: [sensor], groups: [" << kGranted << "]}\n"
                       << "  - {name: analytics, address: 10.20.0.12, roles: [estimator, recommender]}\n";
  const fs::path pki = work / "pki";
  run("CAUSAL_PLANT_PROFILES='" + std::string(CAUSAL_PLANT_PROFILES_BIN) + "' " + script("make-pki.sh") + " '" +
      pki.string() + "' --plant '" + plant.string() + "'");
  return pki;
}

std::vector<std::string> replay_args(const fs::path& pki, const std::string& group) {
  return {SENSOR_REPLAY_BIN, "--domain", std::to_string(kDomain), "--security", pki.string(),
          "--security-identity", "sensor-line-a-sensors", "--features", feature_table(), "--feature-suffix",
          "_meanabs", "--feature-name", "meanabs", "--max-snapshots", std::to_string(kSnapshots), "--speed",
          "120000", "--wait-for", "causal-estimator", "--wait-timeout", "60", "--asset-group", group};
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(GroupGrants, FastDdsRefusesAWriterInAnotherGroupsPartition) {
  const fs::path work = fresh_dir("group_grants_local");
  const fs::path pki = make_plant_pki(work);
  const std::string grant = read_text(pki / "sensor-line-a-sensors" / "permissions.xml");
  EXPECT_NE(grant.find("<partition>causal_twin/group/" + kGranted + "</partition>"), std::string::npos) << grant;
  causal::dds::DdsSettings s = causal::test::loopback_settings(kDomain, "group-grant-probe");
  s.security_dir = pki.string();
  s.security_identity = "sensor-line-a-sensors";
  causal::dds::Participant p(s);
  auto* topic = p.topic<causal_twin::ConditionVectorPubSubType>(causal::dds::topics::kConditionInput);
  for (const auto& [partition, allowed] : std::vector<std::pair<std::string, bool>>{
           {"causal_twin/group/" + kGranted, true}, {"causal_twin/group/" + kOther, false}, {"", false}}) {
    eprosima::fastdds::dds::DataWriterQos qos;
    ASSERT_EQ(p.publisher()->get_datawriter_qos_from_profile(causal::dds::profiles::kConditionInputWriter, qos),
              eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
    if (!partition.empty()) qos.properties().properties().emplace_back("partitions", partition);
    auto* writer = p.publisher()->create_datawriter(topic, qos);
    EXPECT_EQ(writer != nullptr, allowed) << "partition '" << partition << "'";
    if (writer != nullptr) p.publisher()->delete_datawriter(writer);
  }
  fs::remove_all(work);
}

TEST(GroupGrants, EstimatorRefusesAndCountsEveryInputOfAGroupTheWriterIsNotGranted) {
  const fs::path work = fresh_dir("group_grants");
  const fs::path pki = make_plant_pki(work);
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", std::to_string(kDomain), "--security", pki.string(),
                            "--idle-exit", "3", "--max-runtime", "90"},
                           (work / "estimator.log").string());
  ServiceProcess granted("sensor-replay", replay_args(pki, kGranted), (work / "replay_a.log").string());
  ServiceProcess other("sensor-replay", replay_args(pki, kOther), (work / "replay_b.log").string());
  for (ServiceProcess* replay : {&granted, &other}) {
    const auto code = replay->wait(std::chrono::seconds(90));
    ASSERT_TRUE(code.has_value()) << replay->output();
    EXPECT_EQ(*code, 0) << replay->output();
    EXPECT_EQ(summary_count(replay->output(), "causal_twin/condition_input", "sent"), kSnapshots) << replay->output();
  }
  const auto code = estimator.wait(std::chrono::seconds(90));
  ASSERT_TRUE(code.has_value()) << estimator.output();
  const std::string log = estimator.output();
  for (const char* marker : {"summary topic=causal_twin/condition_input", "summary not_processed", "HEALTH RAISED",
                             "summary topic=causal_twin/condition_vector "}) {
    const auto at = log.find(marker);
    if (at != std::string::npos) std::cout << "estimator: " << log.substr(at, log.find('\n', at) - at).substr(0, 160) << "\n";
  }
  EXPECT_EQ(*code, 4) << "refusals make the exit code 4:\n" << log;
  // Every input arrived; the granted group's were all processed, the other group's all refused.
  EXPECT_EQ(summary_count(log, "causal_twin/condition_input", "received"), 2 * kSnapshots) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/condition_input", "not_entitled"), kSnapshots) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/condition_input", "refused"), kSnapshots) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/condition_vector", "sent"), kSnapshots) << log;
  EXPECT_NE(log.find("not_entitled=" + std::to_string(kSnapshots) + " groups=1"), std::string::npos) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED " + kOther + "/input/group_not_entitled/"), 1u) << log;
  EXPECT_EQ(occurrences(log, "group_not_entitled/"), 1u) << "only the other group is refused:\n" << log;
  EXPECT_NE(log.find("may write only its partitions [causal_twin/group/" + kGranted + "]"), std::string::npos) << log;
  EXPECT_EQ(log.find("certificate_expiring"), std::string::npos) << "an 825-day certificate is not near expiry:\n" << log;
  fs::remove_all(work);
}

TEST(CertificateExpiry, EstimatorAlarmsOnceWhenItsOwnCertificateExpiresWithin14Days) {
  const fs::path work = fresh_dir("certificate_expiry");
  const fs::path pki = make_pki(work / "pki");
  run(script("issue-identity.sh") + " '" + pki.string() + "' estimator-short estimator --days 10");
  const std::string domain = "52";
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", domain, "--security", pki.string(), "--security-identity",
                            "estimator-short", "--idle-exit", "2", "--max-runtime", "60"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", domain, "--security", pki.string(), "--features",
                         feature_table(), "--feature-suffix", "_meanabs", "--feature-name", "meanabs", "--max-snapshots",
                         "5", "--speed", "120000", "--wait-for", "causal-estimator", "--wait-timeout", "60",
                         "--asset-group", "line-a"},
                        (work / "replay.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(60)));
  const auto code = estimator.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << estimator.output();
  const std::string log = estimator.output();
  EXPECT_EQ(*code, 0) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/condition_vector", "sent"), 5u) << log;
  EXPECT_EQ(occurrences(log, "HEALTH RAISED estimator/security/certificate_expiring/"), 1u) << log;
  EXPECT_TRUE(log.find("certificate expires in 10.0 days") != std::string::npos ||
              log.find("certificate expires in 9.9 days") != std::string::npos)
      << log;
  // Published on DDS (with any other HEALTH alarm of the run), none dropped.
  EXPECT_GE(summary_count(log, "causal_twin/alarm/health", "sent").value_or(0), 1u) << log;
  EXPECT_EQ(summary_count(log, "causal_twin/alarm/health", "dropped"), 0u) << log;
  fs::remove_all(work);
}
