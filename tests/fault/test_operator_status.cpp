// Operator states on the live path, with real processes on a private loopback domain:
//  * The raw IMS snapshots up to the stopped machine (the last file of IMS test 2: every value at the +-0.002
//    quantisation step) through sensor-replay and causal-estimator: the stop is an operating_change event
//    "machine_stopped", nothing is quarantined or dropped, exit 0 (before: 4 channels stuck, window dropped, exit 4).
//  * The 984-snapshot feature table through estimator, alarm-recommender and causal-recorder: asset_status.csv
//    says "learning n of 140" for the first 140 snapshots (never "healthy" while learning; before: no status at
//    all and "healthy"), then healthy, then alarm with its root cause, and the stopped machine at the end.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "process_expect.hpp"
#include "process_runner.hpp"
#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::test::expect_exit_zero;
using causal::test::ServiceProcess;

namespace {

fs::path work_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_operator_status", name); }

std::string transport() { return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"; }

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// Simple CSV reader for the recorder's files (quoted cells with commas allowed).
std::vector<std::vector<std::string>> read_csv(const fs::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (c == '"') {
        if (quoted && i + 1 < line.size() && line[i + 1] == '"') {
          cells.back() += '"';
          ++i;
        } else {
          quoted = !quoted;
        }
      } else if (c == ',' && !quoted) {
        cells.emplace_back();
      } else {
        cells.back() += c;
      }
    }
    rows.push_back(std::move(cells));
  }
  return rows;
}

}  // namespace

TEST(OperatorStatus, StoppedMachineIsAnOperatingStateNotBadInput) {
  const fs::path work = work_dir("stopped");
  const fs::path dir = work / "ims";
  fs::create_directories(dir);
  const fs::path slice = fs::path(CAUSAL_TWIN_DEPLOY_DIR) / "data" / "ims2-slice";
  for (const char* f : {"2004.02.19.05.52.39.gz", "2004.02.19.06.02.39.gz"}) fs::create_symlink(slice / f, dir / f);
  fs::create_symlink(fs::path(CAUSAL_TWIN_TEST_DATA_DIR) / "ims2-stopped" / "2004.02.19.06.22.39.gz",
                     dir / "2004.02.19.06.22.39.gz");
  const std::string d = std::to_string(causal::test::private_domain_id(64));
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--transport", transport(), "--idle-exit", "3",
                            "--max-runtime", "100"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--transport", transport(), "--ims-dir", dir.string(),
                         "--asset-group", "ims2-end", "--wait-for", "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(90)));
  const auto code = estimator.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << estimator.output();
  const std::string out = estimator.output();
  EXPECT_EQ(*code, 0) << "a stopped machine is not bad input:\n" << out;
  EXPECT_TRUE(contains(out, "OPERATING STATE RAISED ims2-end/machine/machine_stopped/s2")) << out;
  EXPECT_FALSE(contains(out, "DATA QUALITY RAISED")) << out;
  EXPECT_TRUE(contains(out, "summary topic=causal_twin/condition_vector windows_dropped=0")) << out;
  if (!HasFailure()) fs::remove_all(work);
}

TEST(OperatorStatus, AssetStatusSaysLearningThenHealthyThenAlarmAndIsRecorded) {
  const fs::path work = work_dir("status");
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const std::string d = std::to_string(causal::test::private_domain_id(65));
  const std::string t = transport();
  ServiceProcess recorder("causal-recorder",
                          {CAUSAL_RECORDER_BIN, "--domain", d, "--transport", t, "--out", (work / "rec").string(),
                           "--idle-exit", "6", "--max-runtime", "200"},
                          (work / "recorder.log").string());
  ServiceProcess alarm("alarm-recommender",
                       {ALARM_RECOMMENDER_BIN, "--domain", d, "--transport", t, "--idle-exit", "4", "--max-runtime",
                        "200", "--wait-for", "causal-recorder", "--wait-timeout", "60"},
                       (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--transport", t, "--idle-exit", "3", "--max-runtime",
                            "200", "--wait-for", "alarm-recommender", "--wait-for", "causal-recorder"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--transport", t, "--features", table, "--feature-suffix",
                         "_meanabs", "--feature-name", "meanabs", "--channel-names", "bearing1", "bearing2", "bearing3",
                         "bearing4", "--wait-for", "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_TRUE(replay.wait(std::chrono::seconds(150)).has_value()) << replay.output();
  ASSERT_TRUE(estimator.wait(std::chrono::seconds(60)).has_value()) << estimator.output();
  const auto alarm_code = alarm.wait(std::chrono::seconds(60));
  ASSERT_TRUE(alarm_code.has_value()) << alarm.output();
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(recorder, std::chrono::seconds(60)));

  const auto rows = read_csv(work / "rec" / "asset_status.csv");
  ASSERT_GT(rows.size(), 1u) << recorder.output();
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < rows[0].size(); ++i) col[rows[0][i]] = i;
  std::map<std::string, long> first;  // state -> first snapshot index
  std::size_t learning_rows = 0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto& row = rows[r];
    ASSERT_EQ(row.size(), rows[0].size()) << "row " << r;
    const std::string state = row[col.at("state")];
    const long index = std::stol(row[col.at("sample_index")]);
    if (!first.count(state)) first[state] = index;
    if (state == "learning") {
      ++learning_rows;
      EXPECT_EQ(row[col.at("learning_needed")], "140");
    }
    if (state == "healthy") EXPECT_EQ(learning_rows, 139u) << "healthy while learning at snapshot " << index;
  }
  std::cout << "asset_status.csv: " << rows.size() - 1 << " rows, " << learning_rows << " learning; healthy from "
            << first["healthy"] << ", alarm from " << first["alarm"] << "; last: " << rows.back()[col.at("text")]
            << "\n";
  // The recommender's first observation comes with the estimator's first condition-level factors (after its
  // calibration window); from then on one learning row per observation up to 139 of 140.
  EXPECT_EQ(rows[1][col.at("state")], "learning");
  EXPECT_EQ(rows[1][col.at("learning_seen")], "1");
  EXPECT_EQ(learning_rows, 139u);  // 1 of 140 .. 139 of 140; the 140th observation completes the baseline
  EXPECT_GT(first.at("healthy"), first.at("learning"));
  EXPECT_EQ(first.at("alarm"), 541);  // bearing 1's first alarm (docs/results-ims.md: snapshot 541)
  const auto& last = rows.back();
  EXPECT_EQ(last[col.at("state")], "alarm");
  EXPECT_EQ(last[col.at("root_cause_name")], "bearing1");
  EXPECT_TRUE(contains(last[col.at("text")], "not running")) << last[col.at("text")];  // the stopped last snapshot
  EXPECT_TRUE(contains(alarm.output(), "summary topic=causal_twin/asset_status sent=" + std::to_string(rows.size() - 1)))
      << alarm.output();
  if (!HasFailure()) fs::remove_all(work);
}

// A historian that starts late (CI package test: 396 of 428 status rows recorded, every service exit 0).
// The recommender publishes one status change per learning snapshot; its writer keeps the last 64 per group for late
// joiners, so a recorder that matched after ~80 changes silently missed the first ones. With --wait-for
// causal-recorder the recommender takes no input until the recorder's readers are matched, so the recorder gets
// every change even though it starts after the whole table was sent. Without the flag this test fails: the 140
// learning changes go out before the recorder exists and it records only the last 64 of them.
TEST(OperatorStatus, LateRecorderStillGetsEveryStatusChangeWithWaitFor) {
  const fs::path work = work_dir("late_recorder");
  const fs::path table = work / "first300.csv";
  {
    std::ifstream in(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv");
    std::ofstream out(table);
    std::string line;
    for (int n = 0; n <= 300 && std::getline(in, line); ++n) out << line << '\n';  // header + 300 snapshots
  }
  const std::string d = std::to_string(causal::test::private_domain_id(66));
  const std::string t = transport();
  ServiceProcess alarm("alarm-recommender",
                       {ALARM_RECOMMENDER_BIN, "--domain", d, "--transport", t, "--idle-exit", "4", "--max-runtime",
                        "150", "--wait-for", "causal-recorder", "--wait-timeout", "90"},
                       (work / "alarm.log").string());
  // The estimator waits for the recommender only: its input is there, its output queues in the recommender.
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--transport", t, "--idle-exit", "3", "--max-runtime",
                            "150", "--wait-for", "alarm-recommender", "--wait-timeout", "60"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--transport", t, "--features", table.string(),
                         "--feature-suffix", "_meanabs", "--feature-name", "meanabs", "--channel-names", "bearing1",
                         "bearing2", "bearing3", "bearing4", "--wait-for", "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(90)));
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the table is sent: only now does the historian start
  ServiceProcess recorder("causal-recorder",
                          {CAUSAL_RECORDER_BIN, "--domain", d, "--transport", t, "--out", (work / "rec").string(),
                           "--idle-exit", "6", "--max-runtime", "120"},
                          (work / "recorder.log").string());
  const auto alarm_code = alarm.wait(std::chrono::seconds(120));
  ASSERT_TRUE(alarm_code.has_value()) << alarm.output();
  EXPECT_EQ(*alarm_code, 0) << alarm.output();
  EXPECT_TRUE(contains(alarm.output(), "readers matched on every output topic: causal-recorder")) << alarm.output();
  ASSERT_TRUE(estimator.wait(std::chrono::seconds(60)).has_value()) << estimator.output();
  // The recorder may also report condition vectors it never saw (the estimator's ring turned over before it came):
  // that is said in its exit code 4; the status history is what this test is about.
  const auto rec_code = recorder.wait(std::chrono::seconds(60));
  ASSERT_TRUE(rec_code.has_value()) << recorder.output();
  EXPECT_TRUE(*rec_code == 0 || *rec_code == 4) << recorder.output();

  const auto rows = read_csv(work / "rec" / "asset_status.csv");
  ASSERT_GT(rows.size(), 140u) << recorder.output();
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < rows[0].size(); ++i) col[rows[0][i]] = i;
  EXPECT_EQ(rows[1][col.at("learning_seen")], "1") << "the first status change is missing";
  std::cout << "late recorder: asset_status.csv " << rows.size() - 1 << " rows, recorder exit " << *rec_code << "\n";
  EXPECT_TRUE(contains(alarm.output(), "summary topic=causal_twin/asset_status sent=" + std::to_string(rows.size() - 1) +
                                           " failed=0"))
      << alarm.output();
  if (!HasFailure()) fs::remove_all(work);
}
