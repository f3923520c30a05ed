// Crash and restart of alarm-recommender, end to end over DDS (--state-dir): the IMS test-2 feature table
// replayed through causal-estimator; the recommender is killed with SIGKILL once it has raised alarms and
// restarted on the same state directory while the estimator keeps publishing. Checked:
//  * the restarted recommender resumes from its checkpoint (no new baseline: "resumed from checkpoint");
//  * a reader that joins after the restart (transient-local) receives every alarm id raised before the crash;
//  * no alarm id is raised twice across the two processes (the id counters are part of the checkpoint).
#include "dds_observer.hpp"
#include "process_expect.hpp"
#include "ims_feature_replay.hpp"
#include "process_runner.hpp"
#include "service_argv.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <thread>

namespace fs = std::filesystem;
using namespace causal::test;

namespace {

// "ALARM <state> <id> [" lines of a recommender log: id -> states in order.
std::map<std::string, std::vector<std::string>> alarm_lines(const std::string& log) {
  std::map<std::string, std::vector<std::string>> out;
  static const std::regex re(R"(ALARM (raised|escalated|cleared) (\S+) \[)");
  for (auto it = std::sregex_iterator(log.begin(), log.end(), re); it != std::sregex_iterator(); ++it)
    out[(*it)[2].str()].push_back((*it)[1].str());
  return out;
}

}  // namespace

TEST(AlarmRestart, KillNineResumesRepublishesAndNeverReusesIds) {
  const std::string table = causal::test::ims2_feature_table();
  const fs::path work = causal::test::fresh_work_dir("causal_it", "restart");
  fs::create_directories(work / "state");
  // A private domain in 150..230 (the project's range for tests that start processes by hand).
  const std::string d = std::to_string(150 + static_cast<int>(static_cast<unsigned>(getpid()) * 7u % 81u));
  const std::string state = (work / "state").string();
  auto recommender = [&](const std::string& log, bool idle_exit) {
    std::vector<std::string> argv = {ALARM_RECOMMENDER_BIN, "--domain", d, "--state-dir", state, "--max-runtime", "300"};
    if (idle_exit) argv.insert(argv.end(), {"--idle-exit", "5"});
    return std::make_unique<ServiceProcess>("alarm-recommender", argv, (work / log).string());
  };
  auto first = recommender("alarm1.log", false);
  ServiceProcess estimator("causal-estimator", service_argv(CAUSAL_ESTIMATOR_BIN, d, "4", "300", wait_for({"alarm-recommender"})),
                           (work / "estimator.log").string());
  // 60 snapshots per second of wall clock: the kill lands mid-run, the run lasts ~20 s.
  ServiceProcess replay("sensor-replay",
                        ims_feature_replay_argv(SENSOR_REPLAY_BIN, d, table, {"--speed", "36000"}),
                        (work / "replay.log").string());
  ASSERT_TRUE(first->wait_for_output("ALARM raised", std::chrono::seconds(120))) << first->output();
  EXPECT_EQ(first->kill_hard(), 128 + 9);
  const auto before = alarm_lines(first->output());
  ASSERT_FALSE(before.empty());

  auto second = recommender("alarm2.log", true);
  ASSERT_TRUE(second->wait_for_output("re-published from the checkpoint", std::chrono::seconds(120))) << second->output();
  DdsObserver late(std::stoi(d));  // joins after the restart and the republishing
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(240)));
  ASSERT_TRUE(estimator.wait(std::chrono::seconds(120)).has_value()) << estimator.output();
  const auto code = second->wait(std::chrono::seconds(120));
  ASSERT_TRUE(code.has_value()) << second->output();
  EXPECT_EQ(*code, 0) << second->output();

  const std::string out2 = second->output();
  EXPECT_NE(out2.find("resumed from checkpoint: "), std::string::npos) << out2;
  EXPECT_EQ(out2.find("learning the baseline"), std::string::npos) << "the baseline must not be re-learned:\n" << out2;

  std::set<std::string> seen_late;
  for (const auto& a : late.alarms()) seen_late.insert(a.alarm_id());
  for (const auto& [id, states] : before) {
    EXPECT_EQ(seen_late.count(id), 1u) << id << " (raised before the crash) not re-published to a late reader";
  }
  // Raised in the first process, never raised again by the second (a Raised republished is not a new raise:
  // republishing writes no log line).
  const auto after = alarm_lines(out2);
  for (const auto& [id, states] : after) {
    const bool raised_again = std::find(states.begin(), states.end(), "raised") != states.end();
    EXPECT_FALSE(raised_again && before.count(id) > 0) << "alarm id reused after the restart: " << id;
  }
  std::printf("before the crash: %zu alarm ids; after: %zu; a late reader saw %zu\n", before.size(), after.size(),
              seen_late.size());
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
