// The live view as a person sees it, in a real headless Chromium (Debian's chromium, driven by playwright-core):
// sensor-replay paces the 984-snapshot IMS test-2 feature table (mean |x|) at x20000 (about 30 s) through
// causal-estimator and alarm-recommender, twin-web serves the page, drive_twin_web.mjs opens it. Checked:
// no console error; the trend grows while the replay runs; an alarm row appears; a what-if question asked with
// the form is answered; a screenshot is written; and at the end the page and /api/state hold exactly what the
// test's own DDS observer and the feature table say (984 snapshots per channel, the same open alarms).
// Fixed DDS domain 90 (the web helper's range), loopback only.
#include "dds_observer.hpp"
#include "http_test_client.hpp"
#include "browser_driver.hpp"
#include "process_runner.hpp"

#include "causal/io/feature_table.hpp"
#include "causal/io/time_format.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <thread>

namespace fs = std::filesystem;
using causal::test::DdsObserver;
using causal::test::ServiceProcess;
using nlohmann::json;

namespace {

constexpr int kDomain = 90;
const std::vector<std::string> kChannels = {"bearing1", "bearing2", "bearing3", "bearing4"};

std::string utc_minutes(std::int64_t ns) { return causal::io::format_utc(ns).substr(0, 16); }

// The recommender's own count of what it published on a topic ("summary topic=T sent=N").
long published(const std::string& log, const std::string& topic) {
  std::smatch m;
  const std::regex sent("summary topic=" + topic + " sent=(\\d+)");
  return std::regex_search(log, m, sent) ? std::stol(m[1]) : -1;
}

// What the driver read from the final page and from a cold load of the group's
// link, against the test's own DDS observer (the alarms' last events) and the recommender's log.
void check_operator_page(const json& r, const DdsObserver& observer, std::size_t channels, const std::string& alarm_log) {
  ASSERT_TRUE(r.contains("operator") && r.contains("at_load")) << r.dump(1).substr(0, 2000);
  const json& op = r["operator"];
  std::map<std::string, causal_twin::Alarm> last;
  for (const auto& a : observer.alarms()) last[a.alarm_id()] = a;
  // The worst open degradation alarm (highest severity, then the earliest raised), as the status board picks it.
  const causal_twin::Alarm* worst = nullptr;
  std::size_t open_degradation = 0;
  std::set<int> forecast_channels;  // channels with an open condition-level degradation alarm
  for (const auto& [id, a] : last) {
    if (a.state() == causal_twin::CLEARED || a.category() != "degradation") continue;
    ++open_degradation;
    if (id.find("/sample/") == std::string::npos) forecast_channels.insert(a.channel());
    if (worst == nullptr || a.severity() > worst->severity() ||
        (a.severity() == worst->severity() && a.raised_time_ns() < worst->raised_time_ns())) {
      worst = &a;
    }
  }
  ASSERT_NE(worst, nullptr) << "the IMS replay ends with open degradation alarms";
  const std::string severity[] = {"advisory", "warning", "critical"};
  std::printf("operator: worst %s %s, root cause %s, status line: %s\n", worst->alarm_id().c_str(),
              severity[worst->severity()].c_str(), worst->root_cause_name().c_str(), op["status_rows"].dump().c_str());

  // One status line per group: state, worst severity, root cause, the action, the prognosis, learning n of N.
  ASSERT_EQ(op["status_rows"].size(), 1u);
  const json& line = op["status_rows"][0];
  EXPECT_EQ(line["group"], "ims2-shaft1");
  EXPECT_EQ(line["state"], "alarm");
  EXPECT_EQ(line["worst"], severity[worst->severity()] + " \u00d7" + std::to_string(open_degradation));
  EXPECT_EQ(line["root"], worst->root_cause_name());
  EXPECT_EQ(line["action"], worst->action());
  EXPECT_FALSE(worst->action().empty());
  const std::regex prognosis(worst->root_cause_name() + R"(: (warning|critical|end of life)( in ~[0-9.]+ h \([0-9.]+-[0-9.]+ h\), ~2004-02-\d\d \d\d:00 UTC| reached|: unknown.*))");
  EXPECT_TRUE(std::regex_match(line.value("prognosis", std::string()), prognosis)) << line["prognosis"];
  const std::regex learned(R"((\d+) of (\d+))");
  std::smatch m;
  const std::string learning = line.value("learning", std::string());
  ASSERT_TRUE(std::regex_match(learning, m, learned)) << learning;
  EXPECT_EQ(m[1], m[2]) << "the baseline is learned by the end";
  EXPECT_TRUE(line.value("active", false));
  EXPECT_EQ(op["group_links"], json::array({"?group=ims2-shaft1"}));

  // The root-cause node marked in the graph, and only it.
  EXPECT_EQ(op["root_nodes"], json::array({worst->root_cause_channel()}));
  EXPECT_EQ(op["root_labels"], 1);

  // UTC axes and times: the trend's x axis in UTC dates within the replay's days, no snapshot numbers.
  EXPECT_EQ(op["x_title"], "time (UTC)");
  ASSERT_GE(op["x_ticks"].size(), 3u);
  for (const auto& t : op["x_ticks"]) {
    EXPECT_TRUE(std::regex_match(t.get<std::string>(), std::regex(R"(2004-02-(1[2-9])|02-(1[2-9]) \d\d:\d\d)"))) << t;
  }
  for (const char* key : {"stamp", "graph_info", "trend_info"}) {
    EXPECT_NE(op.value(key, std::string()).find(" UTC"), std::string::npos) << key << ": " << op[key];
  }
  EXPECT_EQ(op["alarm_header"][3], "since (UTC)");
  EXPECT_EQ(op["alarm_header"][2], "time scale");

  // Per alarm: its time scale, its raise time in UTC, its whole reason readable without horizontal scrolling.
  std::set<std::string> rows;
  for (const auto& row : op["alarm_rows"]) {
    const std::string id = row["id"].get<std::string>();
    rows.insert(id);
    ASSERT_TRUE(last.count(id)) << id;
    const causal_twin::Alarm& a = last[id];
    const std::string scale = a.category() == "health" ? "twin" : id.find("/sample/") != std::string::npos ? "sample" : "condition";
    EXPECT_EQ(row["scale"], scale) << id;
    EXPECT_EQ(row["since"], utc_minutes(a.raised_time_ns())) << id;
    EXPECT_EQ(row["reason_shown"], a.reason()) << id;
    EXPECT_LE(row["reason_overflow"].get<int>(), 0) << id << ": the reason needs a horizontal scroll";
    if (!a.action().empty()) EXPECT_EQ(row["action"], "Action: " + a.action()) << id;
  }
  EXPECT_EQ(op["alarm_sections"].size() > 0, !rows.empty());
  EXPECT_LE(op["page_overflow_x"].get<int>(), 0) << "the page scrolls sideways";
  EXPECT_LE(op["alarms_overflow_x"].get<int>(), 0) << "the alarm table is wider than its card";
  // The forecast of every channel with an open condition-level degradation alarm, at its three levels; and every
  // prognosis the recommender published reached the page's server.
  EXPECT_EQ(op["prognosis_rows"].size(), 3 * forecast_channels.size()) << op["prognosis_rows"].dump(1);
  EXPECT_GT(published(alarm_log, "causal_twin/prognosis"), 0);

  // The group's link opened cold, with an event stream that never answers: the first response drew it all.
  const json& cold = r["at_load"];
  std::printf("operator: at load of %s: %d points, %zu alarm rows, connection '%s'\n", cold.value("url", std::string()).c_str(),
              cold.value("points", -1), cold["alarm_rows"].size(), cold.value("connection", std::string()).c_str());
  EXPECT_EQ(cold["initial"], "rendered");
  EXPECT_EQ(cold["connection"], "connecting") << "an event reached the page: the test proves nothing about load";
  EXPECT_EQ(cold["selected"], "ims2-shaft1");
  EXPECT_NE(cold.value("url", std::string()).find("?group=ims2-shaft1"), std::string::npos);
  EXPECT_EQ(cold.value("points", 0), static_cast<int>(984 * channels));
  EXPECT_FALSE(cold.value("empty_visible", true)) << "'Waiting for data' shows at load";
  EXPECT_EQ(cold["status_rows"], op["status_rows"]);
  EXPECT_EQ(cold["alarm_rows"], op["alarm_rows"]);
  EXPECT_EQ(cold["root_nodes"], op["root_nodes"]);
  EXPECT_EQ(cold["x_ticks"], op["x_ticks"]);
}

}  // namespace

TEST(TwinWebBrowser, LiveViewShowsTrendsAlarmsAndAnswersWhatIf) {
  causal::test::BrowserFolders dirs;
  ASSERT_TRUE(causal::test::prepare_browser_test(dirs, {"drive_twin_web.mjs"}));
  const fs::path node_dir = dirs.node, out_dir = dirs.out;

  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const auto features = causal::io::read_feature_table(table, "_meanabs");
  const std::size_t snapshots = features.time_ns.size();
  ASSERT_EQ(snapshots, 984u);

  causal::test::clean_stale_shared_memory();
  // Nothing of an earlier run may be read as this run's (a log is read before its process truncates it).
  const fs::path done_file = out_dir / "services_done";
  for (const char* name : {"services_done", "twin_web.png", "twin_web_at_load.png", "twin_web_graph.png", "twin-web.log",
                           "alarm-recommender.log", "causal-estimator.log", "sensor-replay.log", "drive_twin_web.log"}) {
    fs::remove(out_dir / name);
  }
  const std::string d = std::to_string(kDomain);
  DdsObserver observer(kDomain);
  ServiceProcess web("twin-web", {TWIN_WEB_BIN, "--domain", d, "--port", "0", "--max-runtime", "170"},
                     (out_dir / "twin-web.log").string());
  const int port = causal::test::served_port(web, std::chrono::seconds(20));
  ASSERT_GT(port, 0) << web.output();
  ServiceProcess alarm("alarm-recommender",
                       {ALARM_RECOMMENDER_BIN, "--domain", d, "--idle-exit", "5", "--max-runtime", "150"},
                       (out_dir / "alarm-recommender.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "4", "--max-runtime", "150",
                            "--wait-for", "alarm-recommender", "--wait-for", "twin-web", "--wait-for", "test-observer"},
                           (out_dir / "causal-estimator.log").string());
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";
  ServiceProcess driver("drive_twin_web",
                        {NODE_BIN, (node_dir / "drive_twin_web.mjs").string(), "--url", url, "--out",
                         out_dir.string(), "--chromium", CHROMIUM_BIN, "--done-file", done_file.string()},
                        (out_dir / "drive_twin_web.log").string());
  // The replay starts once the page is open, so a slow browser start (a loaded CI machine) cannot miss the run.
  const auto open_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (driver.running() && driver.output().find("drive_twin_web: page loaded") == std::string::npos &&
         std::chrono::steady_clock::now() < open_deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_NE(driver.output().find("drive_twin_web: page loaded"), std::string::npos) << driver.output();
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-suffix", "_meanabs",
                         "--feature-name", "meanabs", "--channel-names", "bearing1", "bearing2", "bearing3", "bearing4",
                         "--speed", "20000", "--wait-for", "causal-estimator", "--wait-timeout", "60"},
                        (out_dir / "sensor-replay.log").string());
  const auto replay_code = replay.wait(std::chrono::seconds(120));
  ASSERT_TRUE(replay_code.has_value()) << replay.output();
  EXPECT_EQ(*replay_code, 0) << replay.output();
  const auto estimator_code = estimator.wait(std::chrono::seconds(60));
  const auto alarm_code = alarm.wait(std::chrono::seconds(60));
  ASSERT_TRUE(estimator_code && alarm_code) << estimator.output() << alarm.output();
  EXPECT_EQ(*estimator_code, 0) << estimator.output();
  EXPECT_EQ(*alarm_code, 0) << alarm.output();
  std::ofstream(done_file) << "done\n";

  const auto driver_code = driver.wait(std::chrono::seconds(90));
  ASSERT_TRUE(driver_code.has_value()) << driver.output();
  const json r = causal::test::driver_result(driver.output());
  ASSERT_TRUE(r.is_object()) << driver.output();
  EXPECT_EQ(*driver_code, 0) << driver.output();
  std::printf("browser: points %d -> %d (snapshot %d -> %d), what-if %s in %d attempt(s), first alarm %s at "
              "snapshot %d, final points %d, open alarms %zu, recommendations shown %d, graph edges %d\n",
              r.value("points_first", -1), r.value("points_second", -1), r.value("index_first", -1),
              r.value("index_second", -1), r.value("whatif_status", std::string("?")).c_str(),
              r.value("whatif_attempts", 0), r.value("first_alarm_id", std::string("?")).c_str(),
              r.value("first_alarm_at_index", -1), r.value("points_final", -1),
              r.contains("open_alarm_ids") ? r["open_alarm_ids"].size() : 0u, r.value("recommendation_items", -1),
              r.value("graph_edges", -1));

  // What the page showed while the replay ran.
  EXPECT_TRUE(r.value("chart_library", false)) << "Chart.js did not load";
  EXPECT_EQ(r["console_errors"].size(), 0u) << r["console_errors"].dump(1);
  EXPECT_EQ(r["page_errors"].size(), 0u) << r["page_errors"].dump(1);
  EXPECT_EQ(r["failed_requests"].size(), 0u) << r["failed_requests"].dump(1);
  EXPECT_EQ(r.value("selected_group", std::string()), "ims2-shaft1");
  EXPECT_EQ(r.value("connection", std::string()), "live") << "the page did not get the state as Server-Sent Events";
  EXPECT_GT(r.value("points_second", 0), r.value("points_first", 0)) << "the trend did not grow during the replay";
  EXPECT_LT(r.value("index_second", 1 << 30), static_cast<int>(snapshots) - 1) << "the replay was over before the second read";
  EXPECT_EQ(r.value("whatif_status", std::string()), "answered") << r["whatif_history"].dump(1);
  EXPECT_EQ(r.value("whatif_rows", 0), 1 + static_cast<int>(kChannels.size())) << r.value("whatif_text", std::string());
  EXPECT_FALSE(r.value("first_alarm_id", std::string()).empty());
  ASSERT_TRUE(fs::exists(out_dir / "twin_web.png"));
  EXPECT_GT(fs::file_size(out_dir / "twin_web.png"), 20000u) << "a screenshot that small is a blank page";
  ASSERT_TRUE(fs::exists(out_dir / "twin_web_graph.png"));
  ASSERT_TRUE(fs::exists(out_dir / "twin_web_at_load.png"));
  EXPECT_GT(fs::file_size(out_dir / "twin_web_at_load.png"), 20000u) << "a screenshot that small is a blank page";

  // The end state, against independent truth: the feature table's rows and the observer's alarms.
  const auto res = causal::test::http_request(port, "GET", "/api/state");
  ASSERT_TRUE(res) << "GET /api/state failed";
  ASSERT_EQ(res->status, 200);
  const json state = json::parse(res->body, nullptr, false);
  std::printf("browser: /api/state at the end: %zu bytes; what-if attempts: %s\n", res->body.size(),
              r["whatif_history"].dump().c_str());
  ASSERT_TRUE(state.is_object());
  ASSERT_EQ(state["groups"].size(), 1u) << state["groups"].dump().substr(0, 400);
  const json& g = state["groups"][0];
  EXPECT_EQ(g["id"], "ims2-shaft1");
  EXPECT_EQ(g["channels"].get<std::vector<std::string>>(), kChannels);
  ASSERT_EQ(g["trend"]["index"].size(), snapshots);
  for (std::size_t c = 0; c < kChannels.size(); ++c) EXPECT_EQ(g["trend"]["values"][c].size(), snapshots);
  // The trend's values are the table's (the estimator publishes what it accepted, unchanged).
  for (std::size_t i : {std::size_t{0}, snapshots / 2, snapshots - 1}) {
    EXPECT_EQ(g["trend"]["index"][i].get<std::size_t>(), i);
    for (std::size_t c = 0; c < kChannels.size(); ++c) {
      EXPECT_DOUBLE_EQ(g["trend"]["values"][c][i].get<double>(), features.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)))
          << "snapshot " << i << " channel " << c + 1;
    }
  }
  EXPECT_EQ(r.value("points_final", 0), static_cast<int>(snapshots * kChannels.size()));
  EXPECT_EQ(r.value("index_final", 0), static_cast<int>(snapshots) - 1);
  EXPECT_EQ(state["counters"]["condition_vectors"].get<std::size_t>(), snapshots);
  EXPECT_EQ(state["counters"]["rejected_vectors"].get<std::size_t>(), 0u);
  EXPECT_EQ(state["counters"]["factor_messages"].get<std::size_t>(),
            observer.factor_batches(causal_twin::CONDITION_LEVEL, causal_twin::FILTER));

  std::map<std::string, causal_twin::Alarm> last_event;
  for (const auto& a : observer.alarms()) last_event[a.alarm_id()] = a;
  std::set<std::string> open_truth;
  for (const auto& [id, a] : last_event) {
    if (a.state() != causal_twin::CLEARED) open_truth.insert(id);
  }
  ASSERT_FALSE(last_event.empty()) << "the pipeline raised no alarm: nothing to show";
  std::set<std::string> served_ids, served_open;
  for (const auto& a : g["alarms"]) {
    served_ids.insert(a["id"].get<std::string>());
    if (a["open"].get<bool>()) served_open.insert(a["id"].get<std::string>());
  }
  std::set<std::string> all_truth;
  for (const auto& [id, a] : last_event) all_truth.insert(id);
  EXPECT_EQ(served_ids, all_truth);
  EXPECT_EQ(served_open, open_truth);
  const auto page_open = r["open_alarm_ids"].get<std::vector<std::string>>();
  EXPECT_EQ(std::set<std::string>(page_open.begin(), page_open.end()), open_truth);
  EXPECT_EQ(state["counters"]["alarm_events"].get<std::size_t>(), observer.alarms().size());
  EXPECT_EQ(state["counters"]["recommendations"].get<std::size_t>(), observer.recommendations().size());
  EXPECT_EQ(state["counters"]["prognoses"].get<long>(), published(alarm.output(), "causal_twin/prognosis"));

  check_operator_page(r, observer, kChannels.size(), alarm.output());

  const int web_code = web.terminate(std::chrono::seconds(10));
  EXPECT_EQ(web_code, 0) << web.output();
  EXPECT_NE(web.output().find("summary topic=causal_twin/condition_vector received=984 duplicates=0 refused=0"),
            std::string::npos)
      << web.output();
  causal::test::clean_stale_shared_memory();
}
