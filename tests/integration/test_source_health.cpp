// Liveliness and deadlines over DDS with real processes ("nothing stalls"): a sensor-replay paced at one
// snapshot per second feeds causal-estimator (health.deadline_s = 4). Checked on causal_twin/alarm with a
// reader in this test:
//  * the replay is killed (SIGKILL) mid-run -> the estimator raises exactly one HEALTH alarm for the group
//    (category health, WARNING, id "<group>/source/health/s<last snapshot>") within the deadline + 3 s;
//  * a new replay of the same group resumes -> that alarm clears (same id);
//  * that replay ends cleanly (it disposes its instance) -> no new HEALTH alarm, even well past the deadline
//    (its participant leaves cleanly; a lost one would raise at once).
// With no deadline (0), the kill is seen as a lost writer when its participant's lease (5 s) expires.
// And the same one level down, in alarm-recommender (health.deadline_s = 4): the estimator killed -> a HEALTH
// alarm "<group>/estimator/health/s<N>" within the deadline + 3 s; a new estimator clears it; everything ends
// cleanly -> nothing new.
#include "dds_observer.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using causal::test::DdsObserver;
using causal::test::ServiceProcess;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kDeadlineS = 4.0;
constexpr double kMarginS = 3.0;  // the estimator checks every 200 ms; alarm delivery over loopback
const std::string kGroup = "health-it";

std::string shipped_params_with_deadline(const fs::path& dir, double deadline_s = kDeadlineS) {
  std::ifstream in(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/estimator.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = std::regex_replace(ss.str(), std::regex("deadline_s: *[0-9.]+"),
                                              "deadline_s: " + std::to_string(deadline_s));
  const fs::path p = dir / "estimator.yaml";
  std::ofstream(p) << text;
  return p.string();
}

// Condition level only, nothing learned first: factors from the first condition vector on.
std::string quick_estimator_params(const fs::path& dir) {
  const fs::path p = dir / "estimator_quick.yaml";
  std::ofstream(p) << "sample_level:\n  enabled: false\n  lag_order: 1\n  include_self_lags: false\n"
                      "  instantaneous_graph: \"\"\n"
                      "  noise: {mode: fixed, q: 1.0e-6, r: 1.0e-2, p0: 1.0, calibration_samples: 4096}\n"
                      "  structure: {calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}\n"
                      "  publish_every: 1024\n  fixed_lag: 0\n"
                      "condition_level:\n  enabled: true\n  feature: meanabs\n  log_transform: true\n"
                      "  window_samples: 0\n  min_samples: 256\n  lag_order: 1\n  include_self_lags: true\n"
                      "  instantaneous_graph: \"\"\n"
                      "  noise: {mode: fixed, q: 1.0e-4, r: 1.0e-2, p0: 1.0, calibration_samples: 100}\n"
                      "  structure: {calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}\n"
                      "  publish_every: 1\n  fixed_lag: 0\n"
                      "health:\n  deadline_s: 30\n";
  return p.string();
}

std::string shipped_alarm_params_with_deadline(const fs::path& dir) {
  std::ifstream in(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/alarms.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = std::regex_replace(ss.str(), std::regex("deadline_s: *[0-9.]+"),
                                              "deadline_s: " + std::to_string(kDeadlineS));
  const fs::path p = dir / "alarms.yaml";
  std::ofstream(p) << text;
  return p.string();
}

bool wait_for_text(ServiceProcess& p, const std::string& text, std::chrono::seconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    if (p.output().find(text) != std::string::npos) return true;
    if (!p.running()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

std::vector<causal_twin::Alarm> health_alarms(const DdsObserver& o) {
  std::vector<causal_twin::Alarm> out;
  for (const auto& a : o.alarms()) {
    if (a.category() == "health") out.push_back(a);
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

}  // namespace

TEST(SourceHealthOverDds, KilledReplayRaisesWithinDeadlineResumedClearsCleanEndRaisesNothing) {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const fs::path work = fs::temp_directory_path() / ("causal_it_health_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  // A private domain in 150..199, from the pid like the other integration tests.
  const std::string d = std::to_string(150 + static_cast<int>((static_cast<unsigned>(getpid()) * 11u + 23u) % 50u));
  DdsObserver observer(std::stoi(d));
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params", shipped_params_with_deadline(work),
                            "--max-runtime", "150"},
                           (work / "estimator.log").string());
  auto replay = [&](const std::string& log, int first, int count) {
    // IMS snapshots are 10 min apart: --speed 600 publishes one per second.
    return std::make_unique<ServiceProcess>(
        "sensor-replay",
        std::vector<std::string>{SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-suffix", "_meanabs",
                                 "--feature-name", "meanabs", "--asset-group", kGroup, "--channel-names", "bearing1",
                                 "bearing2", "bearing3", "bearing4", "--speed", "600", "--first-snapshot",
                                 std::to_string(first), "--max-snapshots", std::to_string(count), "--wait-for",
                                 "causal-estimator", "--wait-timeout", "60"},
        (work / log).string());
  };

  // 1. Killed mid-run: raised within the deadline (+ margin) of the kill, exactly once.
  auto first = replay("replay1.log", 0, 60);
  ASSERT_TRUE(wait_for_text(*first, "replaying", std::chrono::seconds(60))) << first->output();
  ASSERT_TRUE(wait_for_text(estimator, "new asset group 'health-it'", std::chrono::seconds(30))) << estimator.output();
  std::this_thread::sleep_for(std::chrono::seconds(3));  // a few snapshots
  const auto killed_at = Clock::now();
  EXPECT_EQ(first->kill_hard(), 128 + 9);
  const auto raised_seen = wait_for_health(observer, 1, std::chrono::seconds(30));
  ASSERT_TRUE(raised_seen.has_value()) << estimator.output();
  const double after_s = std::chrono::duration<double>(*raised_seen - killed_at).count();
  EXPECT_LE(after_s, kDeadlineS + kMarginS) << "health alarm " << after_s << " s after the kill";
  auto alarms = health_alarms(observer);
  ASSERT_EQ(alarms.size(), 1u);
  const causal_twin::Alarm raised = alarms[0];
  EXPECT_EQ(raised.state(), causal_twin::RAISED);
  EXPECT_EQ(raised.severity(), causal_twin::WARNING);
  EXPECT_EQ(raised.asset_group(), kGroup);
  EXPECT_EQ(raised.alarm_id(), kGroup + "/source/health/s" + std::to_string(raised.sample_index()));
  EXPECT_LT(raised.sample_index(), 60u);
  EXPECT_NE(raised.reason().find("silent"), std::string::npos) << raised.reason();
  // The lease expiry (NOT_ALIVE_NO_WRITERS, 5 s after the kill) must not raise a second alarm.
  std::this_thread::sleep_for(std::chrono::seconds(7));
  EXPECT_EQ(health_alarms(observer).size(), 1u);

  // 2. A new replay of the same group resumes: the alarm clears (same id).
  auto second = replay("replay2.log", 100, 5);
  const auto cleared_seen = wait_for_health(observer, 2, std::chrono::seconds(60));
  ASSERT_TRUE(cleared_seen.has_value()) << second->output() << estimator.output();
  alarms = health_alarms(observer);
  ASSERT_EQ(alarms.size(), 2u);
  EXPECT_EQ(alarms[1].alarm_id(), raised.alarm_id());
  EXPECT_EQ(alarms[1].state(), causal_twin::CLEARED);

  // 3. It ends cleanly: nothing new, even past the deadline.
  const auto code = second->wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << second->output();
  EXPECT_EQ(*code, 0) << second->output();
  std::this_thread::sleep_for(std::chrono::duration<double>(kDeadlineS + kMarginS));
  alarms = health_alarms(observer);
  EXPECT_EQ(alarms.size(), 2u);
  for (std::size_t i = 2; i < alarms.size(); ++i) ADD_FAILURE() << "unexpected: " << alarms[i].alarm_id() << " " << alarms[i].reason();

  const int estimator_code = estimator.terminate();
  const std::string log = estimator.output();
  EXPECT_NE(log.find("summary health sources=1 raised=1 cleared=1 active=0"), std::string::npos) << log;
  std::printf("health alarm %.2f s after the kill (deadline %.0f s); estimator exit %d\n", after_s, kDeadlineS,
              estimator_code);
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

TEST(SourceHealthOverDds, KilledEstimatorRaisesInTheRecommenderRestartedClearsCleanEndRaisesNothing) {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const fs::path work = fs::temp_directory_path() / ("causal_it_health_rec_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string d = std::to_string(150 + static_cast<int>((static_cast<unsigned>(getpid()) * 11u + 37u) % 50u));
  DdsObserver observer(std::stoi(d));
  ServiceProcess recommender("alarm-recommender",
                             {ALARM_RECOMMENDER_BIN, "--domain", d, "--params", shipped_alarm_params_with_deadline(work),
                              "--max-runtime", "150"},
                             (work / "recommender.log").string());
  const std::string est_params = quick_estimator_params(work);
  auto estimator = [&](const std::string& log) {
    return std::make_unique<ServiceProcess>(
        "causal-estimator",
        std::vector<std::string>{CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params", est_params, "--idle-exit", "2",
                                 "--max-runtime", "150", "--wait-for", "alarm-recommender"},
        (work / log).string());
  };
  auto first = estimator("estimator1.log");
  // One snapshot per second, 25 in all: the kill lands mid-run, the second estimator sees the rest.
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-suffix", "_meanabs",
                         "--feature-name", "meanabs", "--asset-group", kGroup, "--channel-names", "bearing1",
                         "bearing2", "bearing3", "bearing4", "--speed", "600", "--max-snapshots", "25", "--wait-for",
                         "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_TRUE(wait_for_text(*first, "new asset group 'health-it'", std::chrono::seconds(60))) << first->output();
  std::this_thread::sleep_for(std::chrono::seconds(4));
  const auto killed_at = Clock::now();
  EXPECT_EQ(first->kill_hard(), 128 + 9);
  const auto raised_seen = wait_for_health(observer, 1, std::chrono::seconds(30));
  ASSERT_TRUE(raised_seen.has_value()) << recommender.output();
  const double after_s = std::chrono::duration<double>(*raised_seen - killed_at).count();
  EXPECT_LE(after_s, kDeadlineS + kMarginS) << "health alarm " << after_s << " s after the kill";
  auto alarms = health_alarms(observer);
  ASSERT_EQ(alarms.size(), 1u);
  const causal_twin::Alarm raised = alarms[0];
  EXPECT_EQ(raised.state(), causal_twin::RAISED);
  EXPECT_EQ(raised.severity(), causal_twin::WARNING);
  EXPECT_EQ(raised.alarm_id(), kGroup + "/estimator/health/s" + std::to_string(raised.sample_index()));
  EXPECT_NE(raised.reason().find("causal factors"), std::string::npos) << raised.reason();

  // A new estimator (the replay waits for it, its ring holds the snapshots meanwhile): cleared.
  auto second = estimator("estimator2.log");
  const auto cleared_seen = wait_for_health(observer, 2, std::chrono::seconds(60));
  ASSERT_TRUE(cleared_seen.has_value()) << second->output() << recommender.output();
  alarms = health_alarms(observer);
  ASSERT_EQ(alarms.size(), 2u);
  EXPECT_EQ(alarms[1].alarm_id(), raised.alarm_id());
  EXPECT_EQ(alarms[1].state(), causal_twin::CLEARED);

  // Everything ends cleanly: the estimator's departure is not a fault.
  const auto replay_code = replay.wait(std::chrono::seconds(90));
  ASSERT_TRUE(replay_code.has_value()) << replay.output();
  EXPECT_EQ(*replay_code, 0) << replay.output();
  ASSERT_TRUE(second->wait(std::chrono::seconds(60)).has_value()) << second->output();
  std::this_thread::sleep_for(std::chrono::duration<double>(kDeadlineS + kMarginS));
  alarms = health_alarms(observer);
  EXPECT_EQ(alarms.size(), 2u);
  for (std::size_t i = 2; i < alarms.size(); ++i) ADD_FAILURE() << "unexpected: " << alarms[i].alarm_id() << " " << alarms[i].reason();
  recommender.terminate();
  const std::string log = recommender.output();
  EXPECT_NE(log.find("summary health sources=1 raised=1 cleared=1 active=0"), std::string::npos) << log;
  std::printf("recommender: health alarm %.2f s after the estimator was killed (deadline %.0f s)\n", after_s, kDeadlineS);
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

TEST(SourceHealthOverDds, WithoutDeadlineAKilledReplayIsALostWriterWhenItsLeaseExpires) {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const fs::path work = fs::temp_directory_path() / ("causal_it_health_lost_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string d = std::to_string(150 + static_cast<int>((static_cast<unsigned>(getpid()) * 11u + 5u) % 50u));
  DdsObserver observer(std::stoi(d));
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params", shipped_params_with_deadline(work, 0.0),
                            "--max-runtime", "120"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-suffix", "_meanabs",
                         "--feature-name", "meanabs", "--asset-group", kGroup, "--channel-names", "bearing1",
                         "bearing2", "bearing3", "bearing4", "--speed", "600", "--max-snapshots", "60", "--wait-for",
                         "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_TRUE(wait_for_text(estimator, "new asset group 'health-it'", std::chrono::seconds(60))) << estimator.output();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const auto killed_at = Clock::now();
  EXPECT_EQ(replay.kill_hard(), 128 + 9);
  const auto raised_seen = wait_for_health(observer, 1, std::chrono::seconds(30));
  ASSERT_TRUE(raised_seen.has_value()) << estimator.output();
  const double after_s = std::chrono::duration<double>(*raised_seen - killed_at).count();
  // Not before the lease (5 s, localhost.xml) can have expired, and within one more lease period.
  EXPECT_GE(after_s, 4.5);
  EXPECT_LE(after_s, 10.0) << "health alarm " << after_s << " s after the kill";
  const auto alarms = health_alarms(observer);
  ASSERT_EQ(alarms.size(), 1u);
  EXPECT_EQ(alarms[0].state(), causal_twin::RAISED);
  EXPECT_NE(alarms[0].reason().find("writer was lost"), std::string::npos) << alarms[0].reason();
  estimator.terminate();
  std::printf("lost writer seen %.2f s after the kill (lease 5 s)\n", after_s);
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
