// Approvals outlive their approver: twin-web keeps every approval on its transient-local intervention writer, so
// a plant that starts AFTER the approval still applies it. On a private loopback domain: twin-web (basic
// authentication, approval lead 40) and a test publisher of two reliable lever recommendations (sim-0000,
// sim-0001); sim-0000's is approved with the page's route (POST /api/approve, CSRF token, authenticated user),
// sim-0001's with causal-approve, which exits once twin-web acknowledged it. Only then do sensor-sim's lever
// plants and causal-recorder start. Checked exactly: the plant applied 2 and refused 0, the recorder wrote the 2
// approvals (approvers: the authenticated operator, not the body's user, and the CLI's), twin-web approved 1 and
// kept 1 (causal-approve's); no token: 403; a second approval of one recommendation: 409. About 10 s.
#include "http_test_client.hpp"
#include "loopback_settings.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"
#include "served_port.hpp"

#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/io/csv_format.hpp"
#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <thread>

namespace fs = std::filesystem;
using causal::test::ServiceProcess;
using nlohmann::json;
using namespace std::chrono_literals;

namespace {

constexpr const char* kAuth = "Authorization: Basic bGF0ZS1vcGVyYXRvcjpsYXRlLXNlY3JldC0yMDI2\r\n";  // late-operator:late-secret-2026

causal_twin::Recommendation lever(const std::string& group, const std::string& id) {
  causal_twin::Recommendation r;
  r.recommendation_id(id);
  r.asset_group(group);
  r.rank(1);
  r.action_kind("upstream_lever");
  r.reliable(true);
  r.intervene_channel(2);
  r.target_channel(1);
  r.delta(std::log(0.75));  // a level change of -25 %
  r.horizon_snapshots(24);
  r.sample_index(5);
  r.text("lower ch2 by 25 %");
  return r;
}

bool page_knows(int port, const std::string& group, const std::string& rec) {
  for (int i = 0; i < 100; ++i) {
    const auto r = causal::test::http_request(port, "GET", "/api/state?group=" + group, kAuth);
    if (r && r->body.find("\"" + rec + "\"") != std::string::npos) return true;
    std::this_thread::sleep_for(100ms);
  }
  return false;
}

std::string csrf_token(int port) {
  const auto page = causal::test::http_request(port, "GET", "/?group=sim-0000", kAuth);
  std::smatch m;
  const std::regex meta(R"re(name="twin-csrf" content="([0-9a-f]+)")re");
  return page && std::regex_search(page->body, m, meta) ? std::string(m[1]) : std::string();
}

}  // namespace

TEST(ApprovalLateReader, APlantStartedAfterTheApprovalsAppliesBoth) {
  const fs::path work = fs::temp_directory_path() / ("approval_late_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const fs::path auth = work / "web.auth";
  std::ofstream(auth) << "late-operator:late-secret-2026\n";
  ::chmod(auth.c_str(), 0600);
  const int domain = causal::test::private_domain_id(43);
  const std::string d = std::to_string(domain);
  ServiceProcess web("twin-web", {TWIN_WEB_BIN, "--domain", d, "--port", "0", "--approval-lead", "40",
                                  "--basic-auth-file", auth.string(), "--max-runtime", "90"},
                     (work / "web.log").string());
  const int port = causal::test::served_port(web, 20s);
  ASSERT_GT(port, 0) << web.output();

  causal::dds::Participant advisor(causal::test::loopback_settings(domain, "test-advisor"));
  causal::dds::TypedWriter<causal_twin::RecommendationPubSubType> recs(advisor, causal::dds::topics::kRecommendation,
                                                                       causal::dds::profiles::kRecommendationWriter);
  std::atomic<bool> stop{false};
  for (auto rec : {lever("sim-0000", "sim-0000/test/1"), lever("sim-0001", "sim-0001/test/1")}) {
    ASSERT_EQ(recs.write(rec, stop, 5s), causal::dds::WriteResult::Ok);
  }
  ASSERT_TRUE(page_knows(port, "sim-0000", "sim-0000/test/1")) << web.output();
  ASSERT_TRUE(page_knows(port, "sim-0001", "sim-0001/test/1")) << web.output();

  // The page's approve button: the what-if form's rules (a POST without the page's token is refused).
  const std::string body = R"({"asset_group":"sim-0000","recommendation_id":"sim-0000/test/1","user":"mallory"})";
  const auto no_token = causal::test::http_request(port, "POST", "/api/approve",
                                                    std::string(kAuth) + "Content-Type: application/json\r\n", body);
  ASSERT_TRUE(no_token.has_value());
  EXPECT_EQ(no_token->status, 403) << no_token->body;
  const std::string token = csrf_token(port);
  ASSERT_EQ(token.size(), 32u);
  const std::string headers = std::string(kAuth) + "Content-Type: application/json\r\nX-Twin-CSRF: " + token + "\r\n";
  const auto approved = causal::test::http_request(port, "POST", "/api/approve", headers, body);
  ASSERT_TRUE(approved.has_value());
  ASSERT_EQ(approved->status, 200) << approved->body;
  const json a = json::parse(approved->body);
  EXPECT_TRUE(a.value("published", false));
  EXPECT_EQ(a.value("approved_by", ""), "late-operator");  // the authenticated user, not the body's
  EXPECT_EQ(a.value("request_id", ""), "sim-0000/sim-0000/test/1@45/late-operator");
  EXPECT_EQ(a.value("start_snapshot_index", 0), 45);  // the recommendation's index 5 + lead 40 (no plant yet)
  EXPECT_EQ(a.value("duration_snapshots", 0), 24);
  EXPECT_NEAR(a.value("change_percent", 0.0), -25.0, 1e-9);
  ASSERT_TRUE(web.wait_for_output("approved from the page", 5s)) << web.output();
  const auto again = causal::test::http_request(port, "POST", "/api/approve", headers, body);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->status, 409) << again->body;  // one approval per recommendation

  // causal-approve publishes once and leaves: twin-web keeps its approval from then on.
  ServiceProcess cli("causal-approve", {CAUSAL_APPROVE_BIN, "--domain", d, "--group", "sim-0001", "--recommendation",
                                        "sim-0001/test/1", "--user", "cli-operator", "--start-index", "60",
                                        "--duration", "24", "--wait-for", "twin-web", "--timeout", "20"},
                     (work / "approve.log").string());
  ASSERT_NO_FATAL_FAILURE(causal::test::expect_exit_zero(cli, 30s));
  ASSERT_TRUE(web.wait_for_output("kept for readers that join later", 10s)) << web.output();

  // Only now the plant and the recorder: neither was running when either approval was published.
  ServiceProcess recorder("causal-recorder", {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(),
                                              "--max-runtime", "60"},
                          (work / "recorder.log").string());
  ServiceProcess sim("sensor-sim", {SENSOR_SIM_BIN, "--domain", d, "--plant", "lever", "--groups", "2", "--seed", "38",
                                    "--snapshots", "120", "--snapshot-rate", "25", "--wait-subscribers", "1",
                                    "--wait-timeout", "30"},
                     (work / "sim.log").string());
  ASSERT_NO_FATAL_FAILURE(causal::test::expect_exit_zero(sim, 40s));
  const auto counts = causal::test::counts_in_last_line(sim.output(), "sensor-sim: sent");
  EXPECT_EQ(counts.at("applied"), 2u) << sim.output();
  EXPECT_EQ(counts.at("refused"), 0u) << sim.output();
  EXPECT_EQ(counts.at("other_groups"), 0u) << sim.output();
  EXPECT_EQ(counts.at("snapshots"), 240u) << sim.output();
  EXPECT_EQ(recorder.terminate(), 0) << recorder.output();
  const auto rows = causal::io::read_csv(work / "rec" / "interventions.csv");
  ASSERT_EQ(rows.rows.size(), 2u) << recorder.output();
  std::set<std::string> approvers;
  for (const auto& row : rows.rows) approvers.insert(row.at(static_cast<std::size_t>(rows.column("approved_by"))));
  EXPECT_EQ(approvers, (std::set<std::string>{"late-operator", "cli-operator"}));

  EXPECT_EQ(web.terminate(), 0) << web.output();
  const auto kept = causal::test::counts_in_last_line(web.output(), "approved=");
  EXPECT_EQ(kept.at("approved"), 1u) << web.output();
  EXPECT_EQ(kept.at("kept"), 1u) << web.output();
  EXPECT_EQ(kept.at("refused"), 0u) << web.output();
  EXPECT_EQ(kept.at("not_entitled"), 0u) << web.output();
  EXPECT_EQ(kept.at("failed"), 0u) << web.output();
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
