// The closed prescriptive loop through the real services over a private loopback domain: sensor-sim --plant
// (two lever plants), causal-estimator (learned order), alarm-recommender, causal-recorder. Both groups alarm on
// channel 1 and get a lever recommendation (act on channel 2); only sim-0000's is approved (causal-approve).
//  * The approval reaches sensor-sim and changes sim-0000's data exactly as the do-operation says (channel 2's
//    level times 1 + p / 100 in the window, against the same plant without it, computed here from level_plant).
//  * sim-0001's recommendation is never applied: its recorded data are the plant without any intervention.
//  * interventions.csv holds the one approval, intervention_outcomes.csv its checked outcome; the recorder's
//    SQLite history (--db) holds the same rows in its tables interventions and intervention_outcomes; twin-web's
//    /api/state shows the approval with its outcome and lever trust under sim-0000 and nothing under sim-0001,
//    live and again when started later on the history alone (--db).
#include "closed_loop_run.hpp"
#include "http_test_client.hpp"
#include "level_plant.hpp"

#include "causal/history/history_store.hpp"
#include "causal/io/csv_format.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <thread>

namespace fs = std::filesystem;
using namespace causal::test;

namespace {

constexpr int kSnapshots = kClosedLoopSnapshots;

// The history table holds the CSV file's rows exactly: same columns, every cell the same (numbers as the same
// double: SQLite prints them with 17 digits, the CSV with the shortest that reads back).
void expect_history_equals_csv(causal::history::HistoryStore& db, const std::string& table_name,
                               const causal::io::CsvTable& csv) {
  const auto& t = causal::history::table(table_name);
  ASSERT_EQ(t.column_names(), csv.header) << table_name;
  const auto rows = db.select(t, {});
  ASSERT_EQ(rows.size(), csv.rows.size()) << table_name;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      const std::string& want = csv.rows[r][c];
      ASSERT_TRUE(rows[r][c].has_value()) << table_name << "." << t.columns[c].name << " is NULL, CSV has " << want;
      if (t.columns[c].type == causal::history::ColumnType::Real) {
        EXPECT_EQ(std::stod(*rows[r][c]), std::stod(want)) << table_name << "." << t.columns[c].name;
      } else {
        EXPECT_EQ(*rows[r][c], want) << table_name << "." << t.columns[c].name;
      }
    }
  }
}

// twin-web's /api/state for one group (its log says the port it chose).
nlohmann::json live_group(ServiceProcess& web, const std::string& group) {
  const std::regex serving(R"(serving http://[0-9.]+:([0-9]+)/)");
  std::smatch m;
  const std::string log = web.output();
  if (!std::regex_search(log, m, serving)) return nullptr;
  const auto reply = http_request(std::stoi(m[1].str()), "GET", "/api/state?group=" + group);
  if (!reply || reply->status != 200) return nullptr;
  return nlohmann::json::parse(reply->body)["group"];
}

// The live view shows the recorded approval and outcome: the same request id, approver, window and outcome fields.
void expect_live_view_shows(ServiceProcess& web, const causal::io::CsvTable& ivs,
                            const causal::io::CsvTable& outcomes) {
  const auto cell = [](const causal::io::CsvTable& t, const char* name) {
    return t.rows.at(0).at(static_cast<std::size_t>(t.column(name)));
  };
  const nlohmann::json g = live_group(web, "sim-0000");
  ASSERT_TRUE(g.is_object()) << web.output();
  ASSERT_EQ(g["interventions"].size(), 1u) << g["interventions"].dump();
  const auto& iv = g["interventions"][0];
  EXPECT_EQ(iv["request_id"], cell(ivs, "request_id"));
  EXPECT_EQ(iv["approved_by"], "it-operator");
  EXPECT_EQ(iv["channel"], std::stoi(cell(ivs, "channel")));
  EXPECT_EQ(iv["change_percent"].get<double>(), std::stod(cell(ivs, "change_percent")));
  EXPECT_EQ(iv["start_index"], std::stoull(cell(ivs, "start_snapshot_index")));
  ASSERT_TRUE(iv["outcome"].is_object()) << iv.dump();
  EXPECT_EQ(iv["outcome"]["status"], "checked");
  EXPECT_EQ(iv["outcome"]["improved"], cell(outcomes, "improved") == "true");
  EXPECT_EQ(iv["outcome"]["inside"], cell(outcomes, "inside") == "true");
  EXPECT_EQ(iv["outcome"]["lever_trust"].get<double>(), std::stod(cell(outcomes, "lever_trust")));
  EXPECT_EQ(iv["outcome"]["observed_percent"].get<double>(), std::stod(cell(outcomes, "observed_percent")));
  const nlohmann::json other = live_group(web, "sim-0001");
  ASSERT_TRUE(other.is_object()) << web.output();
  EXPECT_EQ(other["interventions"], nlohmann::json::array()) << "never approved, never shown";
}

// The recorded condition vectors of `group` (snapshot -> levels of ch1..ch3).
std::map<std::uint64_t, Eigen::Vector3d> recorded_levels(const fs::path& dir, const std::string& group) {
  const auto t = causal::io::read_csv(dir / ("conditions_" + group + "_meanabs.csv"));
  std::map<std::uint64_t, Eigen::Vector3d> out;
  const int c1 = t.column("ch1");
  for (const auto& row : t.rows) {
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v[k] = std::stod(row[static_cast<std::size_t>(c1 + k)]);
    out[std::stoull(row[0])] = v;
  }
  return out;
}

}  // namespace

TEST(ClosedLoop, AnApprovedInterventionReachesThePlantAndIsChecked) {
  const fs::path work = fs::temp_directory_path() / ("causal_it_loop_" + std::to_string(getpid()));
  fs::create_directories(work);
  ClosedLoopRun run(work, private_domain_id(38));
  ASSERT_NO_FATAL_FAILURE(approve_and_finish(run));
  const auto& advice = run.advice;
  const std::string& d = run.d;
  auto& web = run.web;
  auto& alarm = run.alarm;
  EXPECT_TRUE(lever_advice(run.observer, "sim-0001").has_value()) << "the unapproved group had lever advice too";

  // The approval as recorded, and what it did to the data.
  const auto ivs = causal::io::read_csv(work / "rec" / "interventions.csv");
  ASSERT_EQ(ivs.rows.size(), 1u);
  const auto& row = ivs.rows[0];
  EXPECT_EQ(row[static_cast<std::size_t>(ivs.column("approved_by"))], "it-operator");
  EXPECT_EQ(row[static_cast<std::size_t>(ivs.column("recommendation_id"))], advice->recommendation_id());
  const std::uint64_t start = std::stoull(row[static_cast<std::size_t>(ivs.column("start_snapshot_index"))]);
  const double percent = std::stod(row[static_cast<std::size_t>(ivs.column("change_percent"))]);
  ASSERT_LT(start + 24, static_cast<std::uint64_t>(kSnapshots)) << "the window must lie inside the run";
  EXPECT_LT(percent, 0.0);
  for (int g = 0; g < 2; ++g) {
    const std::string group = g == 0 ? "sim-0000" : "sim-0001";
    causal::sim::LevelPlant plant(causal::sim::PlantKind::lever, 38, static_cast<std::uint64_t>(g));
    if (g == 0) ASSERT_EQ(plant.add({1, percent, start, 24}), "");
    const auto levels = recorded_levels(work / "rec", group);
    ASSERT_EQ(levels.size(), static_cast<std::size_t>(kSnapshots)) << group;
    causal::sim::LevelPlant natural(causal::sim::PlantKind::lever, 38, static_cast<std::uint64_t>(g));
    int changed = 0;
    for (std::uint64_t n = 0; n < static_cast<std::uint64_t>(kSnapshots); ++n) {
      const Eigen::VectorXd expected = plant.next(), without = natural.next();
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(levels.at(n)[k], expected[k], 1e-9 * expected[k]) << group << " " << n;
      const bool in_window = g == 0 && n >= start && n < start + 24;
      if (in_window) EXPECT_NEAR(expected[1] / without[1], 1.0 + percent / 100.0, 1e-9);
      changed += (expected - without).norm() > 0.0 && (g == 1 || n < start + 24);
    }
    // Never applied without an approval: sim-0001's data are the plant's own; sim-0000's changed from the start on
    // (and only then).
    EXPECT_EQ(changed, g == 0 ? 24 : 0) << group;
  }
  const auto outcomes = causal::io::read_csv(work / "rec" / "intervention_outcomes.csv");
  ASSERT_EQ(outcomes.rows.size(), 1u) << alarm.output();
  const auto& o = outcomes.rows[0];
  std::printf("outcome: %s\n", o[static_cast<std::size_t>(outcomes.column("text"))].c_str());
  EXPECT_EQ(o[static_cast<std::size_t>(outcomes.column("status"))], "checked");
  EXPECT_EQ(o[static_cast<std::size_t>(outcomes.column("improved"))], "true");
  // The historian: the same approval and outcome, once each (keyed by asset group and request id).
  auto db = causal::history::open_history("sqlite:" + (work / "history.db").string());
  expect_history_equals_csv(*db, "interventions", ivs);
  expect_history_equals_csv(*db, "intervention_outcomes", outcomes);
  db.reset();
  expect_live_view_shows(web, ivs, outcomes);
  EXPECT_EQ(web.terminate(), 0) << web.output();
  // A twin-web started afterwards on the history alone (causal-approve's approval is no longer on any topic).
  ServiceProcess restarted("twin-web", {TWIN_WEB_BIN, "--domain", d, "--port", "0", "--max-runtime", "60", "--db",
                                        "sqlite:" + (work / "history.db").string()},
                           (work / "web2.log").string());
  ASSERT_TRUE(restarted.wait_for_output("serving http", std::chrono::seconds(30))) << restarted.output();
  expect_live_view_shows(restarted, ivs, outcomes);
  EXPECT_EQ(restarted.terminate(), 0) << restarted.output();
  if (!HasFailure()) fs::remove_all(work);
  clean_stale_shared_memory();
}
