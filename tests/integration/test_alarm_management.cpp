// ISA-18.2 alarm management through the real processes (loopback): a simulated run raises alarms; during the run
// causal-alarm-action acknowledges one alarm and shelves another for 6 s; then alarm-recommender is killed (kill -9)
// and restarted on its --state-dir. Checked: the command's exit codes (applied, refused, usage), AssetStatus's
// unacknowledged and shelved counts as alarm-recommender publishes them, the restarted recommender still holding the
// acknowledgement (its republished alarm is flagged, a second acknowledge is refused) and the shelving (republished
// flagged, expiring by itself at the end it was given: its result on causal_twin/alarm_action_result), and
// causal-recorder's alarm_actions.csv and SQLite table holding exactly the three applied actions (acknowledge,
// shelve, the expiry).
#include "loopback_settings.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"
#include "simulated_shaft_table.hpp"

#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/history/history_store.hpp"
#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace causal::test;
using namespace std::chrono_literals;

namespace {

constexpr const char* kGroup = "sim-shaft";

// The test's own participant: the latest AssetStatus, every alarm event and every action result.
class Watch {
 public:
  explicit Watch(int domain)
      : participant_(loopback_settings(domain, "test-watch")),
        status_(participant_, causal::dds::topics::kAssetStatus, causal::dds::profiles::kAssetStatusReader),
        alarms_(participant_, causal::dds::topics::kAlarm, causal::dds::profiles::kAlarmReader),
        results_(participant_, causal::dds::topics::kAlarmActionResult,
                 causal::dds::profiles::kAlarmActionResultReader) {}

  void poll() {
    status_.take_all([this](const causal_twin::AssetStatus& s, const auto&) { status = s; });
    alarms_.take_all([this](const causal_twin::Alarm& a, const auto&) { last_event[a.alarm_id()] = a; });
    results_.take_all([this](const causal_twin::AlarmActionResult& r, const auto&) { results.push_back(r); });
  }
  // Polls until `done` holds or the timeout passes.
  bool until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      poll();
      if (done()) return true;
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(50ms);
    }
  }
  std::vector<std::string> open_alarms() const {
    std::vector<std::string> out;
    for (const auto& [id, a] : last_event) {
      if (a.state() != causal_twin::CLEARED && a.asset_group() == kGroup) out.push_back(id);
    }
    return out;
  }

  causal_twin::AssetStatus status;
  std::map<std::string, causal_twin::Alarm> last_event;
  std::vector<causal_twin::AlarmActionResult> results;

 private:
  causal::dds::Participant participant_;
  causal::dds::TypedReader<causal_twin::AssetStatusPubSubType> status_;
  causal::dds::TypedReader<causal_twin::AlarmPubSubType> alarms_;
  causal::dds::TypedReader<causal_twin::AlarmActionResultPubSubType> results_;
};

std::string source_of(const std::string& id) { return id.substr(0, id.rfind('/')); }

std::vector<std::string> csv_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

TEST(AlarmManagement, AcknowledgeAndShelveDuringARunShowInStatusAndHistory) {
  const fs::path work = fs::temp_directory_path() / ("causal_it_alarm_mgmt_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string table = write_simulated_shaft_table(work);
  const int domain = private_domain_id(17);
  const std::string d = std::to_string(domain);
  Watch watch(domain);
  ServiceProcess recorder("causal-recorder", {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(),
                                              "--db", "sqlite:" + (work / "history.db").string(), "--idle-exit", "30",
                                              "--max-runtime", "300"},
                          (work / "recorder.log").string());
  const std::vector<std::string> alarm_args{ALARM_RECOMMENDER_BIN, "--domain", d, "--max-runtime", "300",
                                           "--state-dir", (work / "state").string()};
  auto alarm_argv = alarm_args;
  alarm_argv.insert(alarm_argv.end(), {"--wait-for", "causal-recorder"});
  auto alarm = std::make_unique<ServiceProcess>("alarm-recommender", alarm_argv, (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator", {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "3",
                                                "--max-runtime", "300", "--wait-for", "alarm-recommender"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay", {SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-name",
                                          "meanabs", "--asset-group", kGroup, "--wait-for", "causal-estimator",
                                          "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, 240s));
  ASSERT_TRUE(estimator.wait(120s).has_value()) << estimator.output();
  // Every snapshot judged: the status line (published when it changes, so not necessarily at the last snapshot)
  // has not changed for 2 s after the estimator, the only source, has left.
  std::uint64_t last_index = 0;
  auto quiet_since = std::chrono::steady_clock::now();
  ASSERT_TRUE(watch.until([&] {
    if (watch.status.sample_index() != last_index) {
      last_index = watch.status.sample_index();
      quiet_since = std::chrono::steady_clock::now();
    }
    return last_index > 300 && std::chrono::steady_clock::now() - quiet_since > 2s;
  }, 60s)) << alarm->output();
  const auto open = watch.open_alarms();
  ASSERT_GE(open.size(), 2u) << "the run must leave two open alarms to act on:\n" << alarm->output();
  ASSERT_EQ(watch.status.unacknowledged_alarms(), open.size()) << watch.status.text();
  ASSERT_EQ(watch.status.shelved_alarms(), 0u);
  const std::string acked = open[0];
  std::string shelved;
  for (const auto& id : open) {
    if (source_of(id) != source_of(acked)) shelved = id;
  }
  ASSERT_FALSE(shelved.empty()) << "two open alarms of different sources needed";

  const auto action = [&](const std::string& name, std::vector<std::string> args) {
    std::vector<std::string> argv{CAUSAL_ALARM_ACTION_BIN, "--domain", d, "--timeout", "20"};
    argv.insert(argv.end(), args.begin(), args.end());
    auto p = std::make_unique<ServiceProcess>("causal-alarm-action", argv, (work / (name + ".log")).string());
    const auto code = p->wait(40s);
    return std::make_pair(code.value_or(-1), p->output());
  };
  // Usage errors: 2, naming what is missing.
  auto [no_user, no_user_out] = action("no_user", {"--group", kGroup, "--alarm", acked, "--ack"});
  EXPECT_EQ(no_user, 2) << no_user_out;
  EXPECT_NE(no_user_out.find("--user"), std::string::npos) << no_user_out;
  auto [no_reason, no_reason_out] = action("no_reason", {"--group", kGroup, "--alarm", shelved, "--shelve", "1",
                                                         "--user", "ann"});
  EXPECT_EQ(no_reason, 2) << no_reason_out;
  EXPECT_NE(no_reason_out.find("--reason"), std::string::npos) << no_reason_out;

  // Acknowledge: applied (0); again: refused (4); an unknown id: refused (4).
  auto [ack, ack_out] = action("ack", {"--group", kGroup, "--alarm", acked, "--ack", "--user", "ann"});
  ASSERT_EQ(ack, 0) << ack_out << alarm->output();
  EXPECT_NE(ack_out.find("applied: acknowledge " + acked + " by ann"), std::string::npos) << ack_out;
  EXPECT_TRUE(watch.until([&] { return watch.status.unacknowledged_alarms() == open.size() - 1; }, 10s))
      << watch.status.unacknowledged_alarms();
  auto [again, again_out] = action("ack_again", {"--group", kGroup, "--alarm", acked, "--ack", "--user", "bob"});
  EXPECT_EQ(again, 4) << again_out;
  EXPECT_NE(again_out.find("is acknowledged"), std::string::npos) << again_out;
  auto [unknown, unknown_out] = action("unknown", {"--group", kGroup, "--alarm", "sim-shaft/9/none/0", "--ack",
                                                   "--user", "ann"});
  EXPECT_EQ(unknown, 4) << unknown_out;
  EXPECT_NE(unknown_out.find("unknown alarm id"), std::string::npos) << unknown_out;

  // Shelve for 6 s (0.1 min): applied, counted in AssetStatus.
  auto [shelve, shelve_out] = action("shelve", {"--group", kGroup, "--alarm", shelved, "--shelve", "0.1",
                                                "--reason", "sensor cable under repair", "--user", "ann"});
  ASSERT_EQ(shelve, 0) << shelve_out << alarm->output();
  EXPECT_TRUE(watch.until([&] { return watch.status.shelved_alarms() == 1; }, 10s)) << alarm->output();
  ASSERT_TRUE(watch.until([&] { return watch.results.size() == 4; }, 10s));
  // Results come per request id (an instance each), not necessarily in the order they were written.
  const auto result_of = [&](const std::function<bool(const causal_twin::AlarmActionResult&)>& which) {
    const auto it = std::find_if(watch.results.begin(), watch.results.end(), which);
    return it == watch.results.end() ? causal_twin::AlarmActionResult() : *it;
  };
  const std::int64_t shelved_until =
      result_of([](const auto& r) { return r.action() == causal_twin::SHELVE; }).until_ns();
  ASSERT_GT(shelved_until, 0);

  // kill -9 and a restart on the same state directory, within the shelving: both survive it.
  const std::string first_log = alarm->output();
  EXPECT_EQ(alarm->kill_hard(), 128 + 9);
  watch.last_event.clear();
  alarm = std::make_unique<ServiceProcess>("alarm-recommender", alarm_args, (work / "alarm2.log").string());
  ASSERT_TRUE(watch.until([&] { return watch.last_event.count(acked) && watch.last_event.count(shelved); }, 20s))
      << alarm->output();
  EXPECT_TRUE(watch.last_event[acked].acknowledged()) << "republished after the restart:\n" << alarm->output();
  EXPECT_FALSE(watch.last_event[acked].shelved());
  EXPECT_TRUE(watch.last_event[shelved].shelved()) << alarm->output();
  EXPECT_FALSE(watch.last_event[shelved].acknowledged());
  auto [after, after_out] = action("ack_after_restart", {"--group", kGroup, "--alarm", acked, "--ack", "--user", "bob"});
  EXPECT_EQ(after, 4) << after_out << alarm->output();
  EXPECT_NE(after_out.find("is acknowledged"), std::string::npos) << after_out;
  const auto expired = [&] {
    return std::any_of(watch.results.begin(), watch.results.end(),
                       [](const auto& r) { return r.request_id().rfind("expired/", 0) == 0; });
  };
  ASSERT_TRUE(watch.until(expired, 20s)) << alarm->output();
  const auto expiry = result_of([](const auto& r) { return r.request_id().rfind("expired/", 0) == 0; });
  EXPECT_EQ(expiry.time_ns(), shelved_until) << "the shelving ends when it was to end";
  EXPECT_GE(expiry.applied_time_ns(), shelved_until);
  EXPECT_EQ(expiry.alarm_id(), shelved);
  // Results: ack applied, ack refused, unknown refused, shelve applied; after the restart ack refused, expiry
  // applied: six.
  ASSERT_EQ(watch.results.size(), 6u);
  EXPECT_EQ(std::count_if(watch.results.begin(), watch.results.end(), [](const auto& r) { return r.applied(); }), 3);

  EXPECT_EQ(alarm->terminate(), 0) << alarm->output();
  const auto summary = alarm->output();
  EXPECT_NE(summary.find("summary topic=causal_twin/alarm_action received=1 applied=0 refused=1 repeated=0 expired=1 "
                         "not_entitled=0"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("alarm management resumed from checkpoint"), std::string::npos) << summary;
  EXPECT_NE(first_log.find("ALARM ACTION"), std::string::npos) << first_log;
  EXPECT_EQ(recorder.terminate(), 0) << recorder.output();

  // The recorder: exactly the three applied actions, in the CSV and in SQLite.
  const auto lines = csv_lines(work / "rec" / "alarm_actions.csv");
  ASSERT_EQ(lines.size(), 4u) << recorder.output();
  EXPECT_EQ(lines[0], "action_id,asset_group,alarm_id,action,user_name,reason,time_utc,until_utc,time_ns,until_ns");
  std::multiset<std::string> kinds;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    for (const char* k : {",acknowledge,", ",shelve,", ",unshelve,"}) {
      if (lines[i].find(k) != std::string::npos) kinds.insert(k);
    }
  }
  EXPECT_EQ(kinds, (std::multiset<std::string>{",acknowledge,", ",shelve,", ",unshelve,"}));
  auto db = causal::history::open_history("sqlite:" + (work / "history.db").string());
  const auto& t = causal::history::table("alarm_actions");
  const auto rows = db->select(t, {});
  ASSERT_EQ(rows.size(), 3u);
  std::map<std::string, std::string> by_action;  // action -> "alarm_id|user|reason"
  for (const auto& r : rows) {
    by_action[r[t.column("action")].value_or("")] = r[t.column("alarm_id")].value_or("") + "|" +
                                                    r[t.column("user_name")].value_or("") + "|" +
                                                    r[t.column("reason")].value_or("");
  }
  EXPECT_EQ(by_action["acknowledge"], acked + "|ann|");
  EXPECT_EQ(by_action["shelve"], shelved + "|ann|sensor cable under repair");
  EXPECT_EQ(by_action["unshelve"], shelved + "|causal-alarm-recommender|shelving expired");
  db.reset();
  fs::remove_all(work);
}
