// The closed loop in the live view, in a real headless Chromium (Debian's chromium, driven by playwright-core):
// the closed-loop run of tests/integration/closed_loop_run.hpp (sensor-sim's lever plants, causal-estimator,
// alarm-recommender, causal-recorder, twin-web with basic authentication). The operator approves sim-0000's lever
// on the page: drive_approve.mjs signs in as it-operator, types another name into the user field, clicks the
// approve button under the recommendation and accepts the confirmation; the page answers "published". After the
// run drive_interventions.mjs opens the page again. Checked: the plant applied exactly that approval (request id,
// approver it-operator: the authenticated user, not the typed one); sim-0000's Interventions card has exactly one
// row, for the recorded request id, status checked, and its approver, lever percent, window, predicted interval,
// observed change, inside/improved and lever trust are the recorder's interventions.csv and
// intervention_outcomes.csv rows as the page formats them; sim-0001's card has none (not approved, not applied);
// no console error. Screenshots in build/tests/browser/output. Private loopback domain; about 50 s (the run is
// paced at 25 snapshots/s).
#include "browser_driver.hpp"
#include "closed_loop_run.hpp"
#include "http_test_client.hpp"

#include "causal/io/csv_format.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace fs = std::filesystem;
using causal::test::ServiceProcess;
using nlohmann::json;
using namespace std::chrono_literals;

namespace {

constexpr const char* kUser = "it-operator";
constexpr const char* kPassword = "closed-loop-2026";

// The page's formats (intervention_panel.js): a signed percent with one decimal, trust with two.
std::string signed_percent(const std::string& cell) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%+.1f %%", std::stod(cell));
  return buf;
}

std::string fixed(const std::string& cell, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::stod(cell));
  return buf;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The card's one row against the recorder's rows (interventions.csv `iv`, intervention_outcomes.csv `o`).
void expect_row_shows(const json& row, const causal::io::CsvTable& ivs, const causal::io::CsvTable& outs) {
  const auto iv = [&](const char* name) { return ivs.rows.at(0).at(static_cast<std::size_t>(ivs.column(name))); };
  const auto o = [&](const char* name) { return outs.rows.at(0).at(static_cast<std::size_t>(outs.column(name))); };
  EXPECT_EQ(row.value("request_id", ""), iv("request_id"));
  EXPECT_EQ(row.value("request_id", ""), o("request_id"));
  EXPECT_EQ(row.value("approved_title", ""), iv("request_id"));
  EXPECT_EQ(row.value("status", ""), "checked");
  EXPECT_EQ(row.value("status", ""), o("status"));
  EXPECT_EQ(row.value("approved", "").rfind(iv("approved_by") + ", ", 0), 0u) << row["approved"];
  EXPECT_EQ(iv("approved_by"), "it-operator");
  EXPECT_TRUE(ends_with(row.value("lever", ""), " " + signed_percent(iv("change_percent")))) << row["lever"];
  EXPECT_EQ(row.value("window", "").rfind("snapshots " + o("start_snapshot_index") + "\u2013" +
                                              o("end_snapshot_index"), 0), 0u) << row["window"];
  EXPECT_EQ(o("start_snapshot_index"), iv("start_snapshot_index"));
  const std::string confidence = std::to_string(std::lround(100.0 * std::stod(o("confidence"))));
  EXPECT_EQ(row.value("predicted", ""), signed_percent(o("predicted_percent")) + " (" + confidence + " % " +
                                            signed_percent(o("predicted_percent_low")) + " to " +
                                            signed_percent(o("predicted_percent_high")) + ")");
  EXPECT_EQ(row.value("observed", ""), signed_percent(o("observed_percent")));
  EXPECT_EQ(row.value("result", ""), std::string(o("inside") == "true" ? "inside" : "outside") +
                                         " the interval \u00b7 " + (o("improved") == "true" ? "improved" : "not improved"));
  EXPECT_EQ(row.value("trust", ""), fixed(o("lever_trust"), 2) + " (" +
                                        (o("lever_claimed") == "true" ? "lever claimed" : "lever withdrawn") + ")");
}

// drive_approve.mjs while the loop runs: the approve button clicked as it-operator. Returns the request id.
std::string approve_on_the_page(const std::string& url, const fs::path& node_dir, const fs::path& out_dir,
                                const fs::path& work) {
  ServiceProcess driver("drive_approve", {NODE_BIN, (node_dir / "drive_approve.mjs").string(), "--url", url, "--out",
                                          out_dir.string(), "--chromium", CHROMIUM_BIN, "--group", "sim-0000", "--user",
                                          kUser, "--password", kPassword, "--typed-user", "mallory"},
                        (work / "drive_approve.log").string());
  const auto code = driver.wait(120s);
  EXPECT_TRUE(code.has_value()) << driver.output();
  const json r = causal::test::driver_result(driver.output());
  EXPECT_TRUE(r.is_object()) << driver.output();
  if (!code || !r.is_object()) return {};
  std::printf("approve: %s\n", r.dump().c_str());
  EXPECT_EQ(*code, 0) << driver.output();
  EXPECT_EQ(r["console_errors"].size(), 0u) << r["console_errors"].dump(1);
  EXPECT_EQ(r["page_errors"].size(), 0u) << r["page_errors"].dump(1);
  EXPECT_EQ(r["failed_requests"].size(), 0u) << r["failed_requests"].dump(1);
  EXPECT_EQ(r.value("/answer/status"_json_pointer, std::string()), "published") << r.dump(1);
  const std::string rec = r.value("recommendation_id", "");
  const std::string id = r.value("/answer/request_id"_json_pointer, std::string());
  // <group>/<recommendation>@<start>/<approver>, as causal-approve names it; the approver is the signed-in user.
  EXPECT_EQ(id.rfind("sim-0000/" + rec + "@", 0), 0u) << id;
  EXPECT_TRUE(ends_with(id, "/it-operator")) << id;
  EXPECT_EQ(r["dialogs"].size(), 1u) << r.dump(1);
  EXPECT_EQ(r.value("/dialogs/0/message"_json_pointer, std::string()).rfind("Approve for sim-0000: change ch2 ", 0), 0u)
      << r.dump(1);
  EXPECT_EQ(r.value("approved_note", ""), "approved by it-operator");
  return id;
}

}  // namespace

TEST(InterventionBrowser, AnOperatorApprovesOnThePageAndSeesTheOutcomeAndLeverTrust) {
  causal::test::BrowserFolders dirs;
  ASSERT_TRUE(
      causal::test::prepare_browser_test(dirs, {"drive_approve.mjs", "drive_interventions.mjs"}, "interventions"));
  const fs::path node_dir = dirs.node, out_dir = dirs.out, work = dirs.work;
  for (const char* name : {"twin_web_interventions.png", "twin_web_interventions_card.png", "twin_web_approve.png"}) {
    fs::remove(out_dir / name);
  }
  const fs::path auth = work / "web.auth";
  std::ofstream(auth) << kUser << ":" << kPassword << "\n";
  fs::permissions(auth, fs::perms::owner_read | fs::perms::owner_write);

  causal::test::ClosedLoopRun run(work, causal::test::private_domain_id(39),
                                  {"--basic-auth-file", auth.string(), "--approval-lead", "25", "--approval-duration",
                                   "24"});
  const int port = causal::test::served_port(run.web, 20s);
  ASSERT_GT(port, 0) << run.web.output();
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";
  const std::string request_id = approve_on_the_page(url, node_dir, out_dir, work);
  ASSERT_FALSE(request_id.empty());
  ASSERT_NO_FATAL_FAILURE(causal::test::finish_run(run));
  EXPECT_NE(run.sim.output().find("intervention " + request_id + " approved by it-operator"), std::string::npos)
      << run.sim.output();
  const auto ivs = causal::io::read_csv(work / "rec" / "interventions.csv");
  const auto outcomes = causal::io::read_csv(work / "rec" / "intervention_outcomes.csv");
  ASSERT_EQ(ivs.rows.size(), 1u) << run.recorder.output();
  ASSERT_EQ(outcomes.rows.size(), 1u) << run.alarm.output();
  EXPECT_EQ(ivs.rows[0].at(static_cast<std::size_t>(ivs.column("request_id"))), request_id);

  ServiceProcess driver("drive_interventions", {NODE_BIN, (node_dir / "drive_interventions.mjs").string(), "--url",
                                                url, "--out", out_dir.string(), "--chromium", CHROMIUM_BIN, "--group",
                                                "sim-0000", "--other", "sim-0001", "--user", kUser, "--password",
                                                kPassword},
                        (work / "drive_interventions.log").string());
  const auto driver_code = driver.wait(90s);
  ASSERT_TRUE(driver_code.has_value()) << driver.output();
  const json r = causal::test::driver_result(driver.output());
  ASSERT_TRUE(r.is_object()) << driver.output();
  EXPECT_EQ(*driver_code, 0) << driver.output();
  EXPECT_EQ(r["console_errors"].size(), 0u) << r["console_errors"].dump(1);
  EXPECT_EQ(r["page_errors"].size(), 0u) << r["page_errors"].dump(1);
  EXPECT_EQ(r["failed_requests"].size(), 0u) << r["failed_requests"].dump(1);
  const json rows = r.value("/group/rows"_json_pointer, json::array());
  ASSERT_EQ(rows.size(), 1u) << r.dump(1);
  std::printf("browser: %s\n", rows[0].dump().c_str());
  EXPECT_EQ(r.value("/group/count"_json_pointer, std::string()), "1");
  expect_row_shows(rows[0], ivs, outcomes);
  EXPECT_EQ(r.value("/other/rows"_json_pointer, json::array()).size(), 0u) << r["other"].dump();
  EXPECT_EQ(r.value("/other/count"_json_pointer, std::string()), "0");
  EXPECT_EQ(r.value("/other/body_text"_json_pointer, std::string()), "No intervention approved for this group.");
  EXPECT_LE(r.value("page_overflow_x", 1), 0) << "the page scrolls sideways";
  for (const char* png : {"twin_web_interventions.png", "twin_web_interventions_card.png", "twin_web_approve.png"}) {
    ASSERT_TRUE(fs::exists(out_dir / png)) << png;
    EXPECT_GT(fs::file_size(out_dir / png), 10000u) << png << ": a screenshot that small is a blank page";
  }
  EXPECT_EQ(run.web.terminate(), 0) << run.web.output();
  const auto kept = causal::test::counts_in_last_line(run.web.output(), "approved=");
  EXPECT_EQ(kept.at("approved"), 1u) << run.web.output();
  EXPECT_EQ(kept.at("refused"), 0u) << run.web.output();
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
