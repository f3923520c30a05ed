// Prognosis end to end over DDS: sensor-replay publishes the IMS test-2 mean-abs features of all 984
// snapshots, causal-estimator and alarm-recommender run with the shipped parameters, causal-recorder writes
// prognosis.csv. Pins the interface the acceptance checks use: the causal_twin/prognosis topic reaches the
// recorder (every message published is written exactly once), prognosis.csv starts with
// asset_group,channel,channel_name,sample_index,time_utc,level,hours,hours_low,hours_high, bearing 1 (channel
// 1) gets rows for all three levels from its first degradation alarm on and none before it, and the alarm's
// decision fields (next level, hours) are in alarms.csv.
#include "process_expect.hpp"
#include "ims_feature_replay.hpp"
#include "process_runner.hpp"
#include "service_argv.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

namespace fs = std::filesystem;
using namespace causal::test;

namespace {

// One CSV line into cells (RFC 4180 quotes; the recorder writes no line breaks inside these files' cells
// except in texts, which these checks do not read past).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

std::vector<std::vector<std::string>> read_rows(const fs::path& path, std::string& header) {
  std::ifstream in(path);
  std::getline(in, header);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(cells(line));
  return rows;
}

long last_number(const std::string& text, const std::string& pattern) {
  std::smatch m;
  long value = -1;
  for (auto it = text.cbegin(); std::regex_search(it, text.cend(), m, std::regex(pattern)); it = m.suffix().first)
    value = std::stol(m[1].str());
  return value;
}

}  // namespace

TEST(Prognosis, ImsReplayPublishesAndRecordsTimeToLevel) {
  const std::string table = causal::test::ims2_feature_table();
  const fs::path work = causal::test::fresh_work_dir("causal_it", "prognosis");
  const std::string d = std::to_string(causal::test::private_domain_id(5));
  ServiceProcess recorder("causal-recorder", service_argv(CAUSAL_RECORDER_BIN, d, "5", "300", {"--out", (work / "rec").string()}),
                          (work / "recorder.log").string());
  ServiceProcess alarm("alarm-recommender", service_argv(ALARM_RECOMMENDER_BIN, d, "4", "300"), (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator",
                           service_argv(CAUSAL_ESTIMATOR_BIN, d, "4", "300", wait_for({"alarm-recommender", "causal-recorder"})),
                           (work / "estimator.log").string());
  ASSERT_NO_FATAL_FAILURE(replay_through(estimator, SENSOR_REPLAY_BIN, d, table, work / "replay.log"));
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(alarm, std::chrono::seconds(120)));
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(recorder, std::chrono::seconds(120)));

  // Exact counting: every prognosis the recommender published is one row, none dropped or repeated.
  const long sent = last_number(alarm.output(), R"(summary topic=causal_twin/prognosis sent=(\d+) failed=0)");
  const long written = last_number(recorder.output(), R"(summary topic=causal_twin/prognosis file=prognosis.csv written=(\d+) duplicates=0)");
  ASSERT_GT(sent, 0) << alarm.output();
  EXPECT_EQ(written, sent) << recorder.output();

  std::string header;
  const auto rows = read_rows(work / "rec" / "prognosis.csv", header);
  EXPECT_EQ(header.rfind("asset_group,channel,channel_name,sample_index,time_utc,level,hours,hours_low,hours_high", 0), 0u)
      << header;
  EXPECT_EQ(static_cast<long>(rows.size()), sent);

  // Bearing 1's first degradation alarm (alarms.csv), and its decision fields.
  std::string alarm_header;
  const auto alarms = read_rows(work / "rec" / "alarms.csv", alarm_header);
  const auto names = cells(alarm_header);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < names.size(); ++i) col[names[i]] = i;
  ASSERT_EQ(col.count("next_level"), 1u) << alarm_header;
  long first_alarm = -1;
  for (const auto& a : alarms) {
    if (a.size() < names.size() || a[col["channel"]] != "1" || a[col["state"]] != "raised" ||
        a[col["category"]] != "degradation")
      continue;
    if (first_alarm < 0) {
      first_alarm = std::stol(a[col["sample_index"]]);
      EXPECT_EQ(a[col["next_level"]], a[col["severity"]] == "advisory" ? "warning" : a[col["severity"]] == "warning"
                                                                                          ? "critical"
                                                                                          : "end_of_life");
    }
  }
  ASSERT_GE(first_alarm, 500) << "no bearing-1 degradation alarm recorded";
  std::printf("bearing 1: first degradation alarm at snapshot %ld; %zu prognosis rows in all\n", first_alarm, rows.size());

  const std::set<std::string> levels{"warning", "critical", "end_of_life"};
  std::map<std::string, long> bearing1_rows, bearing1_known;
  long last_index = -1;
  for (const auto& r : rows) {
    ASSERT_GE(r.size(), 9u);
    EXPECT_EQ(levels.count(r[5]), 1u) << r[5];
    if (r[1] != "1") continue;
    EXPECT_EQ(r[2], "bearing1");
    const long index = std::stol(r[3]);
    EXPECT_GE(index, first_alarm) << "a prognosis before the channel's first alarm";
    last_index = std::max(last_index, index);
    ++bearing1_rows[r[5]];
    if (r[6].empty()) {
      EXPECT_TRUE(r[7].empty() && r[8].empty()) << "unknown hours with an interval";
      continue;
    }
    ++bearing1_known[r[5]];
    const double h = std::stod(r[6]), lo = std::stod(r[7]), hi = std::stod(r[8]);
    EXPECT_LE(lo, h);
    EXPECT_LE(h, hi);
    EXPECT_GE(lo, 0.0);
  }
  for (const auto& l : levels) {
    EXPECT_GT(bearing1_rows[l], 50) << l;  // the alarm stays open for most of the last 450 snapshots
    EXPECT_GT(bearing1_known[l], 0) << l;  // and some prognoses are known
    std::printf("bearing 1 %s: %ld rows, %ld with a known time\n", l.c_str(), bearing1_rows[l], bearing1_known[l]);
  }
  EXPECT_GE(last_index, 970);
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
