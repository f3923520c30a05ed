// Liveliness and deadlines over DDS with real processes ("nothing stalls"): a sensor-replay paced at one
// snapshot per second feeds causal-estimator (health.deadline_s = 4). Checked on causal_twin/alarm with a
// reader in this test:
//  * the replay is killed (SIGKILL) mid-run -> the estimator raises exactly one HEALTH alarm for the group
//    (category health, WARNING, id "<group>/source/health/s<last snapshot>") within the deadline + 3 s;
//  * a new replay of the same group resumes -> that alarm clears (same id);
//  * that replay ends cleanly (it disposes its instance) -> no new HEALTH alarm, even well past the deadline
//    (its participant leaves cleanly; a lost one would raise at once); the snapshots the second replay skipped
//    are one input_lost HEALTH alarm, apart from the liveliness alarms.
// With no deadline (0), the kill is seen as a lost writer when its participant's lease (5 s) expires.
// And the same one level down, in alarm-recommender (health.deadline_s = 4): the estimator killed -> a HEALTH
// alarm "<group>/estimator/health/s<N>" within the deadline + 3 s; a new estimator clears it; everything ends
// cleanly -> nothing new.
#include "condition_level_params.hpp"
#include "dds_observer.hpp"
#include "ims_feature_replay.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using namespace causal::test;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kDeadlineS = 4.0;
constexpr double kMarginS = 3.0;  // the estimator checks every 200 ms; alarm delivery over loopback
const std::string kGroup = "health-it";

// The shipped deploy/config/<name> with health.deadline_s set, written into `dir` under the same name.
std::string shipped_config_with_deadline(const fs::path& dir, const std::string& name, double deadline_s) {
  std::ifstream in(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = std::regex_replace(ss.str(), std::regex("deadline_s: *[0-9.]+"),
                                              "deadline_s: " + std::to_string(deadline_s));
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

bool is_input_lost(const causal_twin::Alarm& a) { return a.alarm_id().find("/input/input_lost/") != std::string::npos; }

// The liveliness alarms (a silent source or estimator); input_lost is counted apart: the estimator's, and the alarm
// engine's (".../observations/input_lost/n": a restarted estimator without its state resumes its output later, and
// the recommender's engine names the observations it never received).
std::vector<causal_twin::Alarm> health_alarms(const DdsObserver& o) {
  std::vector<causal_twin::Alarm> out;
  for (const auto& a : o.alarms()) {
    if (a.category() == "health" && a.kind() != "input_lost") out.push_back(a);
  }
  return out;
}

std::vector<causal_twin::Alarm> input_lost_alarms(const DdsObserver& o) {
  std::vector<causal_twin::Alarm> out;
  for (const auto& a : o.alarms()) {
    if (a.category() == "health" && is_input_lost(a)) out.push_back(a);
  }
  return out;
}

// Waits (bounded) until the observer holds `count` health alarm messages; returns when they were all there.
std::optional<Clock::time_point> wait_for_health(const DdsObserver& o, std::size_t count, std::chrono::seconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    if (health_alarms(o).size() >= count) return Clock::now();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return std::nullopt;
}

// A fresh work folder causal_it_<name>_<pid>, the IMS feature table, a private domain in 150..199 from the
// pid like the other integration tests (`salt`: one per test) and the observer on it.
struct HealthRun {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  fs::path work;
  std::string d;
  DdsObserver observer;
  HealthRun(const std::string& name, unsigned salt)
      : work(fs::temp_directory_path() / ("causal_it_" + name + "_" + std::to_string(getpid()))),
        d(std::to_string(150 + static_cast<int>((static_cast<unsigned>(getpid()) * 11u + salt) % 50u))),
        observer(std::stoi(d)) {
    fs::remove_all(work);
    fs::create_directories(work);
  }
  std::string log(const std::string& name) const { return (work / name).string(); }
  // A service on its shipped parameter file (deploy/config/<file>) with the health deadline deadline_s.
  std::vector<std::string> shipped_argv(const char* bin, const std::string& file, double deadline_s,
                                        const std::string& max_runtime) const {
    return {bin, "--domain", d, "--params", shipped_config_with_deadline(work, file, deadline_s), "--max-runtime",
            max_runtime};
  }
  // The work folder is kept when the test failed; stale shared-memory files are removed either way.
  void finish(bool failed) const {
    if (!failed) fs::remove_all(work);
    causal::test::clean_stale_shared_memory();
  }
  // IMS snapshots are 10 min apart: --speed 600 publishes one per second.
  std::vector<std::string> replay_argv(const std::vector<std::string>& more) const {
    std::vector<std::string> extra{"--asset-group", kGroup, "--speed", "600"};
    extra.insert(extra.end(), more.begin(), more.end());
    return ims_feature_replay_argv(SENSOR_REPLAY_BIN, d, table, extra);
  }
};

// Waits (bounded) for the first health alarm after the kill at `killed_at`; `after_s` is how long after it came.
void wait_for_raised(const DdsObserver& o, Clock::time_point killed_at, const std::function<std::string()>& log,
                     double& after_s) {
  const auto raised_seen = wait_for_health(o, 1, std::chrono::seconds(30));
  ASSERT_TRUE(raised_seen.has_value()) << log();
  after_s = std::chrono::duration<double>(*raised_seen - killed_at).count();
}

// Exactly one health alarm so far, raised as a WARNING.
void expect_one_raised(const DdsObserver& o, causal_twin::Alarm& raised) {
  const auto alarms = health_alarms(o);
  ASSERT_EQ(alarms.size(), 1u);
  raised = alarms[0];
  EXPECT_EQ(raised.state(), causal_twin::RAISED);
  EXPECT_EQ(raised.severity(), causal_twin::WARNING);
}

// `victim` killed (SIGKILL) after `settle`: the first health alarm comes within the deadline (+ margin) of the kill
// (after_s: how long after) and is the only one, raised as a WARNING.
void kill_then_one_raised(ServiceProcess& victim, std::chrono::seconds settle, const DdsObserver& o,
                          const std::function<std::string()>& log, double& after_s, causal_twin::Alarm& raised) {
  std::this_thread::sleep_for(settle);
  const auto killed_at = Clock::now();
  EXPECT_EQ(victim.kill_hard(), 128 + 9);
  ASSERT_NO_FATAL_FAILURE(wait_for_raised(o, killed_at, log, after_s));
  EXPECT_LE(after_s, kDeadlineS + kMarginS) << "health alarm " << after_s << " s after the kill";
  ASSERT_NO_FATAL_FAILURE(expect_one_raised(o, raised));
}

// The source is back: a second health alarm message clears the first (same id).
void expect_cleared(const DdsObserver& o, const causal_twin::Alarm& raised, const std::function<std::string()>& log) {
  const auto cleared_seen = wait_for_health(o, 2, std::chrono::seconds(60));
  ASSERT_TRUE(cleared_seen.has_value()) << log();
  const auto alarms = health_alarms(o);
  ASSERT_EQ(alarms.size(), 2u);
  EXPECT_EQ(alarms[1].alarm_id(), raised.alarm_id());
  EXPECT_EQ(alarms[1].state(), causal_twin::CLEARED);
}

// After a clean end nothing new, even past the deadline; then the service's health summary says so.
void expect_quiet_after_clean_end(const DdsObserver& o) {
  std::this_thread::sleep_for(std::chrono::duration<double>(kDeadlineS + kMarginS));
  const auto alarms = health_alarms(o);
  EXPECT_EQ(alarms.size(), 2u);
  for (std::size_t i = 2; i < alarms.size(); ++i) ADD_FAILURE() << "unexpected: " << alarms[i].alarm_id() << " " << alarms[i].reason();
}

void expect_health_summary(const std::string& log) {
  EXPECT_NE(log.find("summary health sources=1 raised=1 cleared=1 active=0"), std::string::npos) << log;
}

}  // namespace

TEST(SourceHealthOverDds, KilledReplayRaisesWithinDeadlineResumedClearsCleanEndRaisesNothing) {
  const HealthRun run("health", 23u);
  const DdsObserver& observer = run.observer;
  ServiceProcess estimator("causal-estimator",
                           run.shipped_argv(CAUSAL_ESTIMATOR_BIN, "estimator.yaml", kDeadlineS, "150"),
                           run.log("estimator.log"));
  auto replay = [&](const std::string& log, int first, int count) {
    return std::make_unique<ServiceProcess>(
        "sensor-replay",
        run.replay_argv({"--first-snapshot", std::to_string(first), "--max-snapshots", std::to_string(count)}),
        run.log(log));
  };

  // 1. Killed mid-run: raised within the deadline (+ margin) of the kill, exactly once.
  auto first = replay("replay1.log", 0, 60);
  ASSERT_TRUE(first->wait_for_output("replaying", std::chrono::seconds(60))) << first->output();
  ASSERT_TRUE(estimator.wait_for_output("new asset group 'health-it'", std::chrono::seconds(30))) << estimator.output();
  double after_s = 0.0;
  causal_twin::Alarm raised;  // killed after a few snapshots
  ASSERT_NO_FATAL_FAILURE(kill_then_one_raised(*first, std::chrono::seconds(3), observer,
                                               [&] { return estimator.output(); }, after_s, raised));
  EXPECT_EQ(raised.asset_group(), kGroup);
  EXPECT_EQ(raised.alarm_id(), kGroup + "/source/health/s" + std::to_string(raised.sample_index()));
  EXPECT_LT(raised.sample_index(), 60u);
  EXPECT_NE(raised.reason().find("silent"), std::string::npos) << raised.reason();
  // The lease expiry (NOT_ALIVE_NO_WRITERS, 5 s after the kill) must not raise a second alarm.
  std::this_thread::sleep_for(std::chrono::seconds(7));
  EXPECT_EQ(health_alarms(observer).size(), 1u);

  // 2. A new replay of the same group resumes: the alarm clears (same id).
  auto second = replay("replay2.log", 100, 5);
  ASSERT_NO_FATAL_FAILURE(expect_cleared(observer, raised, [&] { return second->output() + estimator.output(); }));

  // 3. It ends cleanly: nothing new, even past the deadline.
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(*second, std::chrono::seconds(60)));
  expect_quiet_after_clean_end(observer);
  // The second replay began at snapshot 100: what the first did not send before its kill never reached the
  // estimator, which says so once, naming the range up to 99 (it cannot know the source skipped it on purpose).
  const auto lost = input_lost_alarms(observer);
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_NE(lost[0].reason().find("..99;"), std::string::npos) << lost[0].reason();

  const int estimator_code = estimator.terminate();
  expect_health_summary(estimator.output());
  std::printf("health alarm %.2f s after the kill (deadline %.0f s); estimator exit %d\n", after_s, kDeadlineS,
              estimator_code);
  run.finish(HasFailure());
}

TEST(SourceHealthOverDds, KilledEstimatorRaisesInTheRecommenderRestartedClearsCleanEndRaisesNothing) {
  const HealthRun run("health_rec", 37u);
  const std::string& d = run.d;
  const DdsObserver& observer = run.observer;
  ServiceProcess recommender("alarm-recommender",
                             run.shipped_argv(ALARM_RECOMMENDER_BIN, "alarms.yaml", kDeadlineS, "150"),
                             run.log("recommender.log"));
  const std::string est_params = write_condition_level_params(run.work / "estimator_quick.yaml");
  auto estimator = [&](const std::string& log) {
    return std::make_unique<ServiceProcess>(
        "causal-estimator",
        std::vector<std::string>{CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params", est_params, "--idle-exit", "2",
                                 "--max-runtime", "150", "--wait-for", "alarm-recommender"},
        run.log(log));
  };
  auto first = estimator("estimator1.log");
  // One snapshot per second, 25 in all: the kill lands mid-run, the second estimator sees the rest.
  ServiceProcess replay("sensor-replay", run.replay_argv({"--max-snapshots", "25"}), run.log("replay.log"));
  ASSERT_TRUE(first->wait_for_output("new asset group 'health-it'", std::chrono::seconds(60))) << first->output();
  double after_s = 0.0;
  causal_twin::Alarm raised;
  ASSERT_NO_FATAL_FAILURE(kill_then_one_raised(*first, std::chrono::seconds(4), observer,
                                               [&] { return recommender.output(); }, after_s, raised));
  EXPECT_EQ(raised.alarm_id(), kGroup + "/estimator/health/s" + std::to_string(raised.sample_index()));
  EXPECT_NE(raised.reason().find("causal factors"), std::string::npos) << raised.reason();

  // A new estimator (the replay waits for it, its ring holds the snapshots meanwhile): cleared.
  auto second = estimator("estimator2.log");
  ASSERT_NO_FATAL_FAILURE(expect_cleared(observer, raised, [&] { return second->output() + recommender.output(); }));

  // Everything ends cleanly: the estimator's departure is not a fault.
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(90)));
  ASSERT_TRUE(second->wait(std::chrono::seconds(60)).has_value()) << second->output();
  expect_quiet_after_clean_end(observer);
  recommender.terminate();
  expect_health_summary(recommender.output());
  std::printf("recommender: health alarm %.2f s after the estimator was killed (deadline %.0f s)\n", after_s, kDeadlineS);
  run.finish(HasFailure());
}

TEST(SourceHealthOverDds, WithoutDeadlineAKilledReplayIsALostWriterWhenItsLeaseExpires) {
  const HealthRun run("health_lost", 5u);
  const DdsObserver& observer = run.observer;
  ServiceProcess estimator("causal-estimator", run.shipped_argv(CAUSAL_ESTIMATOR_BIN, "estimator.yaml", 0.0, "120"),
                           run.log("estimator.log"));
  ServiceProcess replay("sensor-replay", run.replay_argv({"--max-snapshots", "60"}), run.log("replay.log"));
  ASSERT_TRUE(estimator.wait_for_output("new asset group 'health-it'", std::chrono::seconds(60))) << estimator.output();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const auto killed_at = Clock::now();
  EXPECT_EQ(replay.kill_hard(), 128 + 9);
  double after_s = 0.0;
  ASSERT_NO_FATAL_FAILURE(wait_for_raised(observer, killed_at, [&] { return estimator.output(); }, after_s));
  // Not before the lease (5 s, localhost.xml) can have expired, and within one more lease period.
  EXPECT_GE(after_s, 4.5);
  EXPECT_LE(after_s, 10.0) << "health alarm " << after_s << " s after the kill";
  const auto alarms = health_alarms(observer);
  ASSERT_EQ(alarms.size(), 1u);
  EXPECT_EQ(alarms[0].state(), causal_twin::RAISED);
  EXPECT_NE(alarms[0].reason().find("writer was lost"), std::string::npos) << alarms[0].reason();
  estimator.terminate();
  std::printf("lost writer seen %.2f s after the kill (lease 5 s)\n", after_s);
  run.finish(HasFailure());
}
