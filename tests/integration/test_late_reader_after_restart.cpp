// After the services restart, the live view was empty: the open critical alarm was not
// shown again. alarm-recommender published its checkpointed alarms again only when a group's next observation
// arrived, and its recommendations never: with the source finished, nothing came, so a reader that joined after
// the restart (twin-web, a recorder) saw nothing.
//
// Here: the 984-snapshot feature table through causal-estimator and alarm-recommender (--state-dir), watched
// from the start by a DDS observer (the reference: the last event of every alarm id, every recommendation id).
// Then the recommender is killed (SIGKILL) and started again on the same state directory with no estimator and
// no source. Checked: a DDS reader and twin-web that join only after the restart receive the last event of every
// alarm id (same state, same severity, same decision: action, next level and hours to it) and every
// recommendation id; twin-web shows every open alarm as open.
// Fixed DDS domain 227; about 25 s.
#include "dds_observer.hpp"
#include "process_expect.hpp"
#include "ims_feature_replay.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <thread>

namespace fs = std::filesystem;
using namespace causal::test;

namespace {

constexpr int kDomain = 227;

// The alarms the recommender's engines own (degradation, operating changes): the estimator's data-quality and
// every service's HEALTH alarms are not part of the recommender's checkpoint.
std::map<std::string, causal_twin::Alarm> last_events(const std::vector<causal_twin::Alarm>& alarms) {
  std::map<std::string, causal_twin::Alarm> out;
  for (const auto& a : alarms) {
    if (a.category() == "health" || a.category() == "data_quality") continue;
    out[a.alarm_id()] = a;  // in arrival order: the last one stays
  }
  return out;
}

// Equal, or both NaN (unknown).
bool same_number(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

std::set<std::string> recommendation_ids(const std::vector<causal_twin::Recommendation>& recs) {
  std::set<std::string> out;
  for (const auto& r : recs) out.insert(r.recommendation_id());
  return out;
}

std::string http_get(const std::string& url) {
  std::string out;
  FILE* p = popen(("curl -s --max-time 5 '" + url + "'").c_str(), "r");
  if (p == nullptr) return out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof(buf), p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

// Every JSON object with an "id" and an "open" field (twin-web's alarm rows): id -> open.
void collect_alarm_rows(const nlohmann::json& j, std::map<std::string, bool>& out) {
  if (j.is_object()) {
    if (j.contains("id") && j.contains("open") && j["id"].is_string() && j["open"].is_boolean())
      out[j["id"].get<std::string>()] = j["open"].get<bool>();
    for (const auto& [k, v] : j.items()) collect_alarm_rows(v, out);
  } else if (j.is_array()) {
    for (const auto& v : j) collect_alarm_rows(v, out);
  }
}

}  // namespace

TEST(LateReaderAfterRestart, OpenAlarmsAndAdviceReachReadersThatJoinAfterTheServicesRestart) {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const fs::path work = fs::temp_directory_path() / ("causal_it_late_reader_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string d = std::to_string(kDomain);
  const std::string state = (work / "recommender-state").string();
  auto recommender = [&](const std::string& log) {
    return std::make_unique<ServiceProcess>(
        "alarm-recommender",
        std::vector<std::string>{ALARM_RECOMMENDER_BIN, "--domain", d, "--state-dir", state, "--max-runtime", "120"},
        (work / log).string());
  };
  std::map<std::string, causal_twin::Alarm> reference;
  std::set<std::string> reference_recs;
  {
    DdsObserver watcher(kDomain);  // the whole run
    auto first = recommender("recommender1.log");
    ServiceProcess estimator("causal-estimator",
                             {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "3", "--max-runtime", "120",
                              "--state-dir", (work / "estimator-state").string(), "--wait-for", "alarm-recommender"},
                             (work / "estimator.log").string());
    ServiceProcess replay("sensor-replay",
                          ims_feature_replay_argv(SENSOR_REPLAY_BIN, d, table, {"--speed", "60000"}),
                          (work / "replay.log").string());
    const auto replay_code = replay.wait(std::chrono::seconds(90));
    ASSERT_TRUE(replay_code.has_value()) << replay.output();
    ASSERT_EQ(*replay_code, 0) << replay.output();
    ASSERT_NO_FATAL_FAILURE(expect_exit_zero(estimator, std::chrono::seconds(60)));
    // Killed once it has judged all the estimator sent and the watcher acknowledged every message: the reference
    // is then all the run published. A fixed second was too short under load: a recommender still behind was
    // killed between its checkpoint and the publication, and its restart published an alarm the watcher never saw.
    ASSERT_TRUE(first->wait_for_output("caught up:", std::chrono::seconds(90))) << first->output();
    // The services go down hard (a host reboot, a crash): no clean exit of the recommender.
    EXPECT_EQ(first->kill_hard(), 128 + 9);
    watcher.stop();  // what it received is taken
    reference = last_events(watcher.alarms());
    reference_recs = recommendation_ids(watcher.recommendations());
  }
  ASSERT_FALSE(reference.empty()) << "the run raised no alarm: nothing to check";
  std::size_t open = 0;
  for (const auto& [id, a] : reference) open += a.state() != causal_twin::CLEARED ? 1 : 0;
  ASSERT_GT(open, 0u) << "no alarm open at the end of the run";
  std::size_t with_action = 0;
  for (const auto& [id, a] : reference) with_action += a.state() != causal_twin::CLEARED && !a.action().empty() ? 1 : 0;
  ASSERT_GT(with_action, 0u) << "no open alarm carries an action: the decision check below could not fail";

  // Restarted with nothing upstream: no estimator, no source, so no new observation will ever arrive.
  auto second = recommender("recommender2.log");
  ASSERT_TRUE(second->wait_for_output("re-published from the checkpoint", std::chrono::seconds(30))) << second->output();
  ServiceProcess web("twin-web", {TWIN_WEB_BIN, "--domain", d, "--port", "0", "--max-runtime", "60"},
                     (work / "web.log").string());
  DdsObserver late(kDomain);  // joins after the restart
  const std::regex serving(R"(serving http://([0-9.]+):([0-9]+)/)");
  std::smatch m;
  std::string url;
  for (int i = 0; i < 200 && url.empty(); ++i) {
    const std::string log = web.output();
    if (std::regex_search(log, m, serving)) url = "http://" + m[1].str() + ":" + m[2].str();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(url.empty()) << web.output();

  std::map<std::string, causal_twin::Alarm> got;
  std::map<std::string, bool> web_rows;
  for (int i = 0; i < 100; ++i) {  // up to 10 s for discovery and the transient-local history
    got = last_events(late.alarms());
    web_rows.clear();
    const std::string body = http_get(url + "/api/state?group=ims2-shaft1");
    const auto j = nlohmann::json::parse(body, nullptr, false);
    if (!j.is_discarded()) collect_alarm_rows(j, web_rows);
    if (got.size() >= reference.size() && recommendation_ids(late.recommendations()) == reference_recs &&
        web_rows.size() >= reference.size())
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (const auto& [id, want] : reference) {
    const auto it = got.find(id);
    ASSERT_NE(it, got.end()) << id << " (" << (want.state() == causal_twin::CLEARED ? "cleared" : "open")
                             << ") not received by a reader that joined after the restart";
    EXPECT_EQ(it->second.state(), want.state()) << id;
    EXPECT_EQ(it->second.severity(), want.severity()) << id;
    EXPECT_EQ(it->second.sample_index(), want.sample_index()) << id;
    // The decision published with the event (before: republished alarms carried an empty action).
    EXPECT_EQ(it->second.action(), want.action()) << id;
    EXPECT_EQ(it->second.next_level(), want.next_level()) << id;
    EXPECT_TRUE(same_number(it->second.hours_to_next_level(), want.hours_to_next_level())) << id;
    EXPECT_TRUE(same_number(it->second.hours_to_next_level_low(), want.hours_to_next_level_low())) << id;
    EXPECT_TRUE(same_number(it->second.hours_to_next_level_high(), want.hours_to_next_level_high())) << id;
    const auto row = web_rows.find(id);
    ASSERT_NE(row, web_rows.end()) << id << " not in twin-web's state after the restart";
    EXPECT_EQ(row->second, want.state() != causal_twin::CLEARED) << id << ": open/closed differs in twin-web";
  }
  EXPECT_EQ(recommendation_ids(late.recommendations()), reference_recs)
      << "recommendations a late reader received after the restart";
  const std::string out2 = second->output();
  EXPECT_NE(out2.find("recommendations re-published from the checkpoint"), std::string::npos) << out2;
  std::printf("reference: %zu alarm ids (%zu open, %zu with an action), %zu recommendations; after the restart a late reader got %zu "
              "alarm ids and %zu recommendations, twin-web %zu alarm rows\n",
              reference.size(), open, with_action, reference_recs.size(), got.size(), recommendation_ids(late.recommendations()).size(),
              web_rows.size());
  second->terminate();
  web.terminate();
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
