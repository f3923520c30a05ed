// An operator acknowledges an alarm on the live view, in a real headless Chromium (Debian's chromium, driven by
// playwright-core): sensor-replay sends a simulated 400-snapshot shaft (simulated_shaft_table.hpp: two open alarms
// at the end) through causal-estimator and alarm-recommender, twin-web serves the page, causal-recorder records.
// drive_alarm_action.mjs types a user name and clicks the first alarm's Acknowledge button (the page POSTs it with
// its CSRF token). Checked: the answer "applied"; the page then shows the alarm "acknowledged by" the user, without
// an Acknowledge button, and one unacknowledged alarm less in its alarm-system line; alarm-recommender's AssetStatus
// (read by the test's own DDS reader) says the same; causal-recorder's alarm_actions.csv holds exactly that action
// and its asset_status.csv's last line the new count; no console error. Screenshots in build/tests/browser/output.
// Private loopback domain; about 30 s.
#include "http_test_client.hpp"
#include "loopback_settings.hpp"
#include "browser_driver.hpp"
#include "process_runner.hpp"
#include "simulated_shaft_table.hpp"

#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using causal::test::ServiceProcess;
using nlohmann::json;
using namespace std::chrono_literals;

namespace {

constexpr const char* kGroup = "sim-shaft";

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string field; std::getline(s, field, ',');) out.push_back(field);
  return out;
}

// The field of a CSV line under header `name` (the fields read here come before any quoted text).
std::string csv_field(const std::string& header, const std::string& line, const std::string& name) {
  const auto h = split_commas(header), v = split_commas(line);
  for (std::size_t i = 0; i < h.size() && i < v.size(); ++i) {
    if (h[i] == name) return v[i];
  }
  return "?";
}

// The same for a field after any quoted text (asset_status.csv's status text has commas): counted from the end.
std::string csv_field_from_end(const std::string& header, const std::string& line, const std::string& name) {
  const auto h = split_commas(header), v = split_commas(line);
  for (std::size_t i = 0; i < h.size() && h.size() - i <= v.size(); ++i) {
    if (h[i] == name) return v[v.size() - (h.size() - i)];
  }
  return "?";
}

}  // namespace

TEST(AlarmActionBrowser, OperatorClicksAcknowledgeAndEveryViewShowsIt) {
  causal::test::BrowserFolders dirs;
  ASSERT_TRUE(causal::test::prepare_browser_test(dirs, {"drive_alarm_action.mjs"}, "alarm_action"));
  const fs::path node_dir = dirs.node, out_dir = dirs.out, work = dirs.work;
  for (const char* name : {"twin_web_alarm_action.png", "twin_web_alarm_action_card.png"}) fs::remove(out_dir / name);
  const std::string table = causal::test::write_simulated_shaft_table(work);
  const int domain = causal::test::private_domain_id(19);
  const std::string d = std::to_string(domain);

  causal::dds::Participant watch(causal::test::loopback_settings(domain, "test-watch"));
  causal::dds::TypedReader<causal_twin::AssetStatusPubSubType> status_reader(
      watch, causal::dds::topics::kAssetStatus, causal::dds::profiles::kAssetStatusReader);
  causal_twin::AssetStatus status;
  const auto status_until = [&](const std::function<bool()>& done, std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      status_reader.take_all([&](const causal_twin::AssetStatus& s, const auto&) { status = s; });
      if (done()) return true;
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(50ms);
    }
  };
  ServiceProcess recorder("causal-recorder", {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(),
                                              "--max-runtime", "150"}, (work / "recorder.log").string());
  ServiceProcess web("twin-web", {TWIN_WEB_BIN, "--domain", d, "--port", "0", "--max-runtime", "150"},
                     (work / "twin-web.log").string());
  const int port = causal::test::served_port(web, 20s);
  ASSERT_GT(port, 0) << web.output();
  ServiceProcess alarm("alarm-recommender", {ALARM_RECOMMENDER_BIN, "--domain", d, "--max-runtime", "150",
                                             "--wait-for", "causal-recorder"}, (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator", {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "3",
                                                "--max-runtime", "150", "--wait-for", "alarm-recommender",
                                                "--wait-for", "twin-web"}, (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay", {SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-name",
                                          "meanabs", "--asset-group", kGroup, "--wait-for", "causal-estimator",
                                          "--wait-timeout", "60"}, (work / "replay.log").string());
  const auto replay_code = replay.wait(120s);
  ASSERT_TRUE(replay_code.has_value()) << replay.output();
  ASSERT_EQ(*replay_code, 0) << replay.output();
  ASSERT_TRUE(estimator.wait(60s).has_value()) << estimator.output();
  // Every snapshot judged: the status line (published when it changes) quiet for 2 s after the estimator left.
  std::uint64_t last_index = 0;
  auto quiet_since = std::chrono::steady_clock::now();
  ASSERT_TRUE(status_until([&] {
    if (status.sample_index() != last_index) {
      last_index = status.sample_index();
      quiet_since = std::chrono::steady_clock::now();
    }
    return last_index > 300 && std::chrono::steady_clock::now() - quiet_since > 2s;
  }, 60s)) << alarm.output();
  const unsigned unacknowledged = status.unacknowledged_alarms();
  ASSERT_GE(unacknowledged, 1u) << "the run must leave an alarm to acknowledge:\n" << alarm.output();

  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";
  ServiceProcess driver("drive_alarm_action", {NODE_BIN, (node_dir / "drive_alarm_action.mjs").string(), "--url", url,
                                               "--out", out_dir.string(), "--chromium", CHROMIUM_BIN, "--user", "ann"},
                        (work / "drive_alarm_action.log").string());
  const auto driver_code = driver.wait(90s);
  ASSERT_TRUE(driver_code.has_value()) << driver.output();
  const json r = causal::test::driver_result(driver.output());
  ASSERT_TRUE(r.is_object()) << driver.output();
  EXPECT_EQ(*driver_code, 0) << driver.output();
  std::printf("browser: acknowledged %s: answer '%s'; handling '%s' -> '%s'; %s -> %s\n",
              r.value("alarm_id", std::string("?")).c_str(), r.value("ack_text", std::string("?")).c_str(),
              r.value("/before/text"_json_pointer, std::string("?")).c_str(),
              r.value("/after/text"_json_pointer, std::string("?")).c_str(),
              r.value("health_before", std::string("?")).c_str(), r.value("health_after", std::string("?")).c_str());
  EXPECT_EQ(r["console_errors"].size(), 0u) << r["console_errors"].dump(1);
  EXPECT_EQ(r["page_errors"].size(), 0u) << r["page_errors"].dump(1);
  EXPECT_EQ(r["failed_requests"].size(), 0u) << r["failed_requests"].dump(1);
  const std::string id = r.value("alarm_id", std::string());
  ASSERT_FALSE(id.empty()) << driver.output();
  EXPECT_EQ(r.value("ack_status", std::string()), "applied") << r.value("ack_text", std::string());
  EXPECT_EQ(r.value("ack_text", std::string()), "acknowledge " + id + ": applied");
  EXPECT_EQ(r.value("/before/text"_json_pointer, std::string()), "unacknowledged");
  EXPECT_EQ(r.value("/after/text"_json_pointer, std::string()), "acknowledged by ann");
  EXPECT_EQ(r["/after/buttons"_json_pointer], json::array({"Shelve"})) << "no Acknowledge button once acknowledged";
  const std::string count_before = "Alarm system: " + std::to_string(unacknowledged) + " unacknowledged,";
  const std::string count_after = "Alarm system: " + std::to_string(unacknowledged - 1) + " unacknowledged,";
  EXPECT_EQ(r.value("health_before", std::string()).rfind(count_before, 0), 0u) << r["health_before"];
  EXPECT_EQ(r.value("health_after", std::string()).rfind(count_after, 0), 0u) << r["health_after"];
  EXPECT_LE(r.value("page_overflow_x", 1), 0) << "the page scrolls sideways";
  for (const char* png : {"twin_web_alarm_action.png", "twin_web_alarm_action_card.png"}) {
    ASSERT_TRUE(fs::exists(out_dir / png)) << png;
    EXPECT_GT(fs::file_size(out_dir / png), 20000u) << png << ": a screenshot that small is a blank page";
  }

  // The same on the bus, in alarm-recommender's own counts and in the recorder's files.
  EXPECT_TRUE(status_until([&] { return status.unacknowledged_alarms() == unacknowledged - 1; }, 10s))
      << status.unacknowledged_alarms();
  EXPECT_EQ(alarm.terminate(), 0) << alarm.output();
  EXPECT_NE(alarm.output().find("summary topic=causal_twin/alarm_action received=1 applied=1 refused=0 repeated=0 "
                                "expired=0 not_entitled=0"), std::string::npos) << alarm.output();
  EXPECT_EQ(web.terminate(), 0) << web.output();
  EXPECT_EQ(recorder.terminate(), 0) << recorder.output();
  const auto actions = lines_of(work / "rec" / "alarm_actions.csv");
  ASSERT_EQ(actions.size(), 2u) << recorder.output();
  EXPECT_EQ(csv_field(actions[0], actions[1], "action"), "acknowledge");
  EXPECT_EQ(csv_field(actions[0], actions[1], "alarm_id"), id);
  EXPECT_EQ(csv_field(actions[0], actions[1], "user_name"), "ann");
  const auto statuses = lines_of(work / "rec" / "asset_status.csv");
  ASSERT_GE(statuses.size(), 2u);
  EXPECT_EQ(csv_field_from_end(statuses[0], statuses.back(), "unacknowledged_alarms"), std::to_string(unacknowledged - 1));
  fs::remove_all(work);
}
