// A revocation takes effect on a running pipeline, without anyone restarting it.
// A secured causal-estimator (with checkpoints) is fed by two sensor-replays: the plant's sensor (group
// line-a) and a retired sensor (group line-r) whose host keeps its files. revoke-identity.sh then rewrites the
// PKI's revocation list (empty since make-pki.sh). Every process watching that list restarts itself in place
// (revocation_watch.hpp) and its new participant refuses the retired identity:
// * the estimator restarts within a minute of the revocation (measured: kRevocationPoll = 10 s + the restart);
// * after it, no input of line-r reaches it; line-a's snapshots are all processed exactly once across the
//   restart (checkpoints; the replay rewinds to the restarted estimator's progress).
// Fixed loopback domain 53 (tests/security/CMakeLists.txt); about 30 s.
#include "../fault/delivery_checks.hpp"
#include "pki_fixture.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <regex>
#include <thread>

using causal::test::expect_exit_zero;
using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

constexpr const char* kDomain = "53";
// The plant's sensor runs about 25 s, so the estimator restarts while it still sends (the watch polls every 10 s
// from the estimator's start; the revocation comes 5 s after it): the restart is in the middle of its stream.
constexpr std::uint64_t kPlantSnapshots = 500;
const std::string kRestartLine = "restarting with the new revocation list";

std::string feature_table() {
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
}

// 0.05 s per snapshot (10 minutes apart in the data).
std::vector<std::string> replay_args(const fs::path& pki, const std::string& identity, const std::string& group,
                                     std::uint64_t snapshots) {
  return {SENSOR_REPLAY_BIN, "--domain", kDomain, "--security", pki.string(), "--security-identity", identity,
          "--features", feature_table(), "--feature-suffix", "_meanabs", "--feature-name", "meanabs",
          "--max-snapshots", std::to_string(snapshots), "--speed", "12000", "--wait-for", "causal-estimator",
          "--wait-timeout", "60", "--asset-group", group};
}

// "asset 'G': F frames (...), L snapshots lost after a restart, N condition vectors in" of one run's summary; nullopt
// when the group is absent.
std::optional<std::uint64_t> conditions_in(const std::string& run_log, const std::string& group) {
  const std::regex line("asset '" + group + R"(': \d+ frames \([^)]*\), \d+ snapshots lost after a restart, (\d+) condition vectors in)");
  std::smatch m;
  if (!std::regex_search(run_log, m, line)) return std::nullopt;
  return std::stoull(m[1].str());
}

bool wait_for_text(ServiceProcess& p, const std::string& text, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (p.output().find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

}  // namespace

TEST(LiveRevocation, RunningEstimatorRefusesARevokedSensorWithinAMinute) {
  const fs::path work = fresh_dir("live_revocation");
  const fs::path pki = make_pki(work / "pki");
  ASSERT_TRUE(fs::exists(pki / "identity_ca.crl")) << "make-pki.sh writes an empty revocation list";
  run(script("issue-identity.sh") + " '" + pki.string() + "' retired-sensor sensor");
  fs::copy(pki, work / "retired-host", fs::copy_options::recursive);  // the retired host keeps its files
  // The plant's sensor host gets the new list later: its replay does not restart with the estimator (a sensor
  // that does restarts from its first snapshot and the estimator skips what it processed: counted apart).
  fs::copy(pki, work / "plant-host", fs::copy_options::recursive);
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", kDomain, "--security", pki.string(), "--state-dir",
                            (work / "state").string(), "--idle-exit", "4", "--max-runtime", "110"},
                           (work / "estimator.log").string());
  ServiceProcess plant("sensor-replay", replay_args(work / "plant-host", "sensor", "line-a", kPlantSnapshots),
                       (work / "plant.log").string());
  ServiceProcess retired("sensor-replay", replay_args(work / "retired-host", "retired-sensor", "line-r", 600),
                         (work / "retired.log").string());
  // Both feed the estimator for a while before the revocation (checked below from its first run's summary).
  ASSERT_TRUE(wait_for_text(estimator, "DDS-Security on", std::chrono::seconds(40))) << estimator.output();
  std::this_thread::sleep_for(std::chrono::seconds(5));
  const auto revoked_at = std::chrono::steady_clock::now();
  run(script("revoke-identity.sh") + " '" + pki.string() + "' retired-sensor");
  ASSERT_TRUE(wait_for_text(estimator, kRestartLine, std::chrono::seconds(60))) << estimator.output();
  const double restart_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - revoked_at).count();
  std::cout << "revocation: the estimator restarted " << restart_s << " s after revoke-identity.sh\n";
  EXPECT_LT(restart_s, 60.0);

  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(plant, std::chrono::seconds(90)));
  const auto code = estimator.wait(std::chrono::seconds(90));
  ASSERT_TRUE(code.has_value()) << estimator.output();
  const std::string log = estimator.output();
  EXPECT_EQ(*code, 0) << log;
  retired.terminate(std::chrono::seconds(5));
  const std::size_t cut = log.rfind(kRestartLine);
  ASSERT_NE(cut, std::string::npos) << log;
  const std::string before = log.substr(0, cut), after = log.substr(cut);
  std::cout << "revocation: condition inputs processed before/after the restart: line-a "
            << conditions_in(before, "line-a").value_or(0) << "/" << conditions_in(after, "line-a").value_or(0)
            << ", line-r " << conditions_in(before, "line-r").value_or(0) << "/"
            << conditions_in(after, "line-r").value_or(0) << "\n";
  EXPECT_GT(conditions_in(before, "line-r").value_or(0), 0u) << "the retired sensor fed it before:\n" << before;
  EXPECT_EQ(conditions_in(after, "line-r").value_or(0), 0u) << "no line-r input after the restart:\n" << after;
  // line-a: every snapshot processed exactly once, before or after the restart.
  EXPECT_EQ(conditions_in(before, "line-a").value_or(0) + conditions_in(after, "line-a").value_or(0), kPlantSnapshots)
      << log;
  EXPECT_EQ(summary_count(after, "causal_twin/condition_input", "lost"), 0u) << after;
  fs::remove_all(work);
}
