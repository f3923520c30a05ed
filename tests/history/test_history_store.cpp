// The historian's database (common/history) on real databases: an SQLite file and a PostgreSQL 15 server this
// test starts itself (tests/support/postgres_server.sh; skipped without PostgreSQL 15, failed where
// CAUSAL_TWIN_REQUIRE_ALL=1). The same checks on both backends: a row stored twice is stored once, cells come
// back typed as they went in, a batch is one transaction, ranges and retention by data time, bad cells refused.
#include "causal/history/history_store.hpp"
#include "causal/history/json_cells.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using causal::history::HistoryError;
using causal::history::HistoryStore;
using causal::history::RangeQuery;
using causal::history::Row;
using causal::history::table;

namespace {

std::string run_capture(const std::string& cmd, int& status) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) {
    status = -1;
    return out;
  }
  std::array<char, 512> buf{};
  while (fgets(buf.data(), buf.size(), p) != nullptr) out += buf.data();
  const int rc = pclose(p);
  status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

// One PostgreSQL server for the whole test program.
struct Postgres {
  std::string dir, url;
  int status = -1;
  Postgres() {
    dir = "/tmp/causal-history-pg-" + std::to_string(getpid());
    url = run_capture(std::string(CAUSAL_TWIN_TESTS_SUPPORT) + "/postgres_server.sh start " + dir, status);
  }
  ~Postgres() {
    int ignored = 0;
    run_capture(std::string(CAUSAL_TWIN_TESTS_SUPPORT) + "/postgres_server.sh stop " + dir, ignored);
  }
};

Postgres& postgres() {
  static Postgres server;
  return server;
}

std::size_t t_col(const char* name) { return table("alarms").column(name); }

Row condition(const std::string& group, int snapshot, long long time_ns, const std::string& values) {
  return {group, "meanabs", std::to_string(snapshot), std::to_string(time_ns), "", "[\"a\",\"b\"]", values};
}

class HistoryStoreTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (GetParam() == "sqlite") {
      // One folder per test (the parameterised name "Test/sqlite" is no file name: '/' replaced).
      std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
      for (char& c : name) c = c == '/' ? '-' : c;
      dir_ = fs::temp_directory_path() / ("causal-history-" + std::to_string(getpid()) + "-" + name);
      fs::remove_all(dir_);
      url_ = "sqlite:" + (dir_ / "sub" / "history.db").string();  // the folder is created
    } else {
      Postgres& pg = postgres();
      if (pg.status == 77) {
        if (std::getenv("CAUSAL_TWIN_REQUIRE_ALL") != nullptr) FAIL() << "PostgreSQL 15 is required here";
        GTEST_SKIP() << "no PostgreSQL 15 (deploy/install_deps.sh installs it)";
      }
      ASSERT_EQ(pg.status, 0) << "PostgreSQL did not start";
      url_ = pg.url;
      clear_ = true;  // one server for every test: each starts from empty tables
    }
    store_ = causal::history::open_history(url_);
    if (clear_) {
      // Retention far in the future of every row: deletes everything (tables without a time are cleared by key).
      store_->apply_retention(1.0, 9'000'000'000'000'000'000LL);
    }
  }
  void TearDown() override {
    store_.reset();
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path dir_;
  std::string url_;
  bool clear_ = false;
  std::unique_ptr<HistoryStore> store_;
};

TEST_P(HistoryStoreTest, ARowStoredTwiceIsStoredOnceAndComesBackTyped) {
  const auto& t = table("condition_vectors");
  store_->add("condition_vectors", condition("pump-7", 0, 1000, "[1.5,2]"));
  store_->add("condition_vectors", condition("pump-7", 1, 2000, "[1.25,null]"));
  EXPECT_EQ(store_->commit(), 2u);
  // Re-delivered (a replay after a restart): the key (asset_group, feature, snapshot) says it is there already.
  store_->add("condition_vectors", condition("pump-7", 1, 2000, "[1.25,null]"));
  store_->add("condition_vectors", condition("pump-7", 2, 3000, "[3,4]"));
  EXPECT_EQ(store_->commit(), 1u);
  EXPECT_EQ(store_->count(t), 3u);
  const auto rows = store_->select(t, RangeQuery{"pump-7", {}, {}, 0});
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1][2], std::optional<std::string>("1"));
  EXPECT_EQ(rows[1][3], std::optional<std::string>("2000"));
  EXPECT_EQ(rows[1][4], std::optional<std::string>(""));  // empty text stays text, not NULL
  const auto values = causal::history::parse_json_number_array(*rows[1][6]);
  ASSERT_TRUE(values.has_value());
  ASSERT_EQ(values->size(), 2u);
  EXPECT_DOUBLE_EQ(*(*values)[0], 1.25);
  EXPECT_FALSE((*values)[1].has_value());
  EXPECT_EQ(store_->max_integer(t, "snapshot", "pump-7"), std::optional<std::int64_t>(2));
  EXPECT_EQ(store_->max_integer(t, "snapshot", "pump-8"), std::nullopt);
  EXPECT_EQ(store_->earliest(t), std::optional<std::int64_t>(1000));
}

// The closed loop's tables: keyed by (asset_group, request_id) like their topics, so a replayed approval or outcome
// is stored once; cells come back typed; retention (a time far in the future) does not delete them.
TEST_P(HistoryStoreTest, InterventionsAndOutcomesAreStoredOncePerRequestId) {
  const auto& iv = table("interventions");
  const auto& out = table("intervention_outcomes");
  const Row approval{"g/r1@250/ann", "loop-g", "3", "-25.5", "250", "1700000000000000000", "2023-11-14 22:13:20",
                     "24", "g/r1", "2", "ann", "1700000600000000000", "2023-11-14 22:23:20"};
  const Row outcome{"g/r1@250/ann", "loop-g", "g/r1", "3", "2", "250", "273", "checked", "-12.5", "-20", "-5", "0.9",
                    "-10.25", "true", "false", "0.75", "true", "observed -10.2 %"};
  store_->add("interventions", approval);
  store_->add("intervention_outcomes", outcome);
  EXPECT_EQ(store_->commit(), 2u);
  store_->add("interventions", approval);  // re-delivered after a restart
  store_->add("intervention_outcomes", outcome);
  EXPECT_EQ(store_->commit(), 0u);
  store_->apply_retention(1.0, 9'000'000'000'000'000'000LL);
  const auto ivs = store_->select(iv, RangeQuery{"loop-g", {}, {}, 0});
  const auto outs = store_->select(out, RangeQuery{"loop-g", {}, {}, 0});
  ASSERT_EQ(ivs.size(), 1u);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(ivs[0][iv.column("approved_by")], std::optional<std::string>("ann"));
  EXPECT_EQ(ivs[0][iv.column("start_time_ns")], std::optional<std::string>("1700000000000000000"));
  EXPECT_EQ(std::stod(*ivs[0][iv.column("change_percent")]), -25.5);
  EXPECT_EQ(outs[0][out.column("inside")], std::optional<std::string>("true"));
  EXPECT_EQ(outs[0][out.column("improved")], std::optional<std::string>("false"));
  EXPECT_EQ(outs[0][out.column("end_snapshot_index")], std::optional<std::string>("273"));
  EXPECT_EQ(std::stod(*outs[0][out.column("lever_trust")]), 0.75);
}

TEST_P(HistoryStoreTest, RangesAndRetentionFollowTheDataTime) {
  const auto& t = table("condition_vectors");
  for (int i = 0; i < 10; ++i) store_->add("condition_vectors", condition("g", i, 1000LL * (i + 1), "[1,2]"));
  store_->add("condition_vectors", condition("other", 0, 5000, "[1,2]"));
  ASSERT_EQ(store_->commit(), 11u);
  EXPECT_EQ(store_->select(t, RangeQuery{"g", 3000, 6000, 0}).size(), 4u);
  EXPECT_EQ(store_->select(t, RangeQuery{"", 5000, 5000, 0}).size(), 2u);
  EXPECT_EQ(store_->select(t, RangeQuery{"g", {}, {}, 3}).size(), 3u);
  // Keep one day before "now" = 1 day + 5500 ns: the rows at 1000..5000 ns go (5 of g, 1 of other).
  EXPECT_EQ(store_->apply_retention(1.0, 86'400'000'000'000LL + 5500), 6u);
  EXPECT_EQ(store_->count(t), 5u);
}

TEST_P(HistoryStoreTest, AlarmsKeyedByEventAndTimesAsUtcText) {
  const auto& t = table("alarms");
  auto alarm = [](const std::string& state, const std::string& index, const std::string& time) {
    Row r(table("alarms").columns.size(), std::string());
    r[t_col("alarm_id")] = "g/1/cusum/1";
    r[t_col("state")] = state;
    r[t_col("severity")] = "warning";
    r[t_col("asset_group")] = "g";
    r[t_col("channel")] = "1";
    r[t_col("sample_index")] = index;
    r[t_col("time_utc")] = time;
    r[t_col("score")] = "nan";  // the CSV's unknown number
    return r;
  };
  store_->add("alarms", alarm("raised", "10", "2004-02-12 10:32:39"));
  store_->add("alarms", alarm("cleared", "20", "2004-02-13 10:32:39"));
  store_->add("alarms", alarm("raised", "10", "2004-02-12 10:32:39"));  // the same event again
  EXPECT_EQ(store_->commit(), 2u);
  const auto rows = store_->select(t, RangeQuery{"g", 1076580000LL * 1'000'000'000LL, {}, 0});  // from 2004-02-12 10:00
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][t_col("state")], std::optional<std::string>("raised"));
  EXPECT_EQ(rows[0][t_col("channel")], std::optional<std::string>("1"));
  EXPECT_EQ(rows[0][t_col("threshold")], std::nullopt);  // an empty number is NULL
}

TEST_P(HistoryStoreTest, ABadCellIsRefusedNamingItsColumnAndNothingOfTheBatchIsLost) {
  Row bad = condition("g", 0, 1000, "[1,2]");
  bad[2] = "twelve";
  try {
    store_->add("condition_vectors", bad);
    FAIL() << "a non-number in an integer column was accepted";
  } catch (const HistoryError& e) {
    EXPECT_NE(std::string(e.what()).find("snapshot"), std::string::npos) << e.what();
  }
  EXPECT_THROW(store_->add("no_such_table", {}), HistoryError);
  EXPECT_THROW(store_->add("condition_vectors", Row{"too", "short"}), HistoryError);
  store_->add("condition_vectors", condition("g", 0, 1000, "[1,2]"));
  EXPECT_EQ(store_->commit(), 1u);
  EXPECT_EQ(store_->count(table("condition_vectors")), 1u);
}

TEST_P(HistoryStoreTest, ASecondConnectionSeesWhatTheFirstCommitted) {
  store_->add("condition_vectors", condition("g", 0, 1000, "[1,2]"));
  ASSERT_EQ(store_->commit(), 1u);
  auto reader = causal::history::open_history(url_);  // twin-web next to the recorder
  EXPECT_EQ(reader->count(table("condition_vectors")), 1u);
}

INSTANTIATE_TEST_SUITE_P(Backends, HistoryStoreTest, ::testing::Values("sqlite", "postgresql"),
                         [](const auto& param_info) { return param_info.param; });

TEST(HistoryUrl, AnUnknownSchemeOrAnEmptyPathIsRefused) {
  EXPECT_THROW(causal::history::open_history("mysql://x"), HistoryError);
  EXPECT_THROW(causal::history::open_history("sqlite:"), HistoryError);
}

}  // namespace
