// causal-recorder against real DDS publishers (private domains 161..163, loopback transport), then
// causal-report on what it recorded. Every wait is bounded; only processes started here are signalled,
// by pid; leftover Fast DDS shared-memory files of dead processes are cleaned with `fastdds shm clean`.
#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"

#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <memory>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

constexpr int kG = 3;
const std::int64_t kT0 = 1076581959LL * 1000000000LL;  // 2004-02-12 10:32:39 UTC
const std::int64_t kDt = 600LL * 1000000000LL;          // one snapshot every 10 min
constexpr std::uint64_t kSnapshots = 12;

std::string channel(int c) { return "Bearing " + std::to_string(c); }

std::vector<std::string> names_of(int k) {  // model convention, self lags included
  std::vector<std::string> n;
  for (int j = 1; j <= kG; ++j) if (j != k) n.push_back("x" + std::to_string(k) + std::to_string(j));
  for (int j = 1; j <= kG; ++j) n.push_back("xL" + std::to_string(k) + std::to_string(j));
  return n;
}
double factor_value(std::uint64_t n, int k, std::size_t i, bool smoothed) {
  return 0.3 * std::sin(0.2 * static_cast<double>(n) + k + 0.7 * static_cast<double>(i)) + (smoothed ? 0.01 : 0.0);
}
double factor_sd(std::uint64_t n, int k, std::size_t i) { return 0.05 + 0.01 * k + 0.001 * static_cast<double>(i) + 0.1 / (1.0 + static_cast<double>(n));
}
double feature_value(std::uint64_t n, int c) { return 0.05 * c * std::exp(0.08 * static_cast<double>(n)); }

using causal::test::slurp;

std::vector<std::string> lines_of(const fs::path& p) {
  std::vector<std::string> lines;
  std::istringstream in(slurp(p));
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::vector<std::string> split(const std::string& line) {  // only for lines without quoted cells
  std::vector<std::string> cells;
  std::size_t start = 0;
  for (std::size_t c = line.find(','); c != std::string::npos; c = line.find(',', start)) {
    cells.push_back(line.substr(start, c - start));
    start = c + 1;
  }
  cells.push_back(line.substr(start));
  return cells;
}

bool on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string d; std::getline(dirs, d, ':');) {
    if (!d.empty() && ::access((fs::path(d) / name).c_str(), X_OK) == 0) return true;
  }
  return false;
}

class RecorderIntegration : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("causal_recorder_it_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    asset_ = "it " + std::to_string(::getpid()) + "/shaft,1";  // needs sanitising
    file_asset_ = causal::io::safe_file_component(asset_);
  }

  void TearDown() override {
    // Still running only if a check failed: stop it (ours, by pid), politely first so that it releases its
    // shared-memory files, then for good.
    for (pid_t pid : std::vector<pid_t>(children_)) {
      ::kill(pid, SIGTERM);
      if (wait_exit(pid, 10s) == -1) {
        ::kill(pid, SIGKILL);
        int status = 0;
        ::waitpid(pid, &status, 0);
      }
    }
    children_.clear();
    writers_.reset();
    participant_.reset();
    // Every process of ours is gone now; the tool removes only segments whose owners are dead.
    if (on_path("fastdds")) run_sync({"fastdds", "shm", "clean"}, dir_ / "shm_clean.log");
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(dir_, ec);
  }

  pid_t spawn(const std::vector<std::string>& argv, const fs::path& log) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = -1;
    const int rc = posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return -1;
    children_.push_back(pid);
    return pid;
  }

  // Exit code of our child, or -1 if it did not end within `limit`.
  int wait_exit(pid_t pid, std::chrono::milliseconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        children_.erase(std::remove(children_.begin(), children_.end(), pid), children_.end());
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(20ms);
    }
    return -1;
  }

  int run_sync(const std::vector<std::string>& argv, const fs::path& log, std::chrono::seconds limit = 60s) {
    const pid_t pid = spawn(argv, log);
    if (pid < 0) return -2;
    return wait_exit(pid, limit);
  }

  pid_t start_recorder(int domain, const std::vector<std::string>& extra) {
    std::vector<std::string> argv{CAUSAL_RECORDER_BIN, "--domain", std::to_string(domain), "--out",
                                  (dir_ / "run").string(), "--max-runtime", "60"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return spawn(argv, dir_ / "recorder.log");
  }

  struct Writers {
    explicit Writers(causal::dds::Participant& p)
        : conditions(p, causal::dds::topics::kConditionVector, causal::dds::profiles::kConditionVectorWriter),
          factors(p, causal::dds::topics::kCausalFactors, causal::dds::profiles::kCausalFactorsWriter),
          alarms(p, causal::dds::topics::kAlarm, causal::dds::profiles::kAlarmWriter),
          recommendations(p, causal::dds::topics::kRecommendation, causal::dds::profiles::kRecommendationWriter) {}
    causal::dds::TypedWriter<causal_twin::ConditionVectorPubSubType> conditions;
    causal::dds::TypedWriter<causal_twin::CausalFactorBatchPubSubType> factors;
    causal::dds::TypedWriter<causal_twin::AlarmPubSubType> alarms;
    causal::dds::TypedWriter<causal_twin::RecommendationPubSubType> recommendations;
  };

  // Publisher on the loopback profile; waits (bounded) until the recorder's readers matched.
  void open_publisher(int domain) {
    causal::dds::DdsSettings s;
    s.profile_files = {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml",
                       std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"};
    s.domain_id = domain;
    s.participant_name = "report-integration-test";
    participant_ = std::make_unique<causal::dds::Participant>(s);
    writers_ = std::make_unique<Writers>(*participant_);
    ASSERT_TRUE(writers_->conditions.wait_for_readers(1, 20s, stop_)) << slurp(dir_ / "recorder.log");
    ASSERT_TRUE(writers_->factors.wait_for_readers(1, 20s, stop_));
    ASSERT_TRUE(writers_->alarms.wait_for_readers(1, 20s, stop_));
    ASSERT_TRUE(writers_->recommendations.wait_for_readers(1, 20s, stop_));
  }

  // A batch with the one outcome block k (the estimator sends all G in one batch; single blocks let the tests
  // send outcomes out of order, twice, or never).
  causal_twin::CausalFactorBatch factors(std::uint64_t n, int k, causal_twin::EstimateKind kind,
                                         causal_twin::TimeScale scale = causal_twin::CONDITION_LEVEL) const {
    causal_twin::CausalFactorBatch m;
    m.asset_group(asset_);
    m.kind(kind);
    m.time_scale(scale);
    m.feature("rms");
    m.channel_count(kG);
    m.lag_order(1);
    m.sample_index(n);
    m.time_ns(kT0 + static_cast<std::int64_t>(n) * kDt);
    causal_twin::OutcomeFactors o;
    o.outcome(static_cast<uint16_t>(k));
    o.outcome_name(channel(k));
    const auto names = names_of(k);
    o.factor_names(names);
    std::vector<double> v, sd;
    for (std::size_t i = 0; i < names.size(); ++i) {
      v.push_back(factor_value(n, k, i, kind == causal_twin::FIXED_LAG_SMOOTHER));
      sd.push_back(factor_sd(n, k, i));
    }
    o.factors(v);
    o.factor_std(sd);
    o.nis_mean(1.0 + 0.1 * k);
    o.innovation_count(1);
    m.outcomes().push_back(std::move(o));
    return m;
  }

  void publish(causal_twin::CausalFactorBatch m) {
    ASSERT_EQ(writers_->factors.write(m, stop_), causal::dds::WriteResult::Ok);
  }

  // Waits (bounded) until the recorder has `rows` data rows in `file`: the recorder flushes after every
  // batch, so this is the recorder's own confirmation. (A writer's wait_for_acknowledgments is no proof:
  // it also succeeds once the reader has left, and KEEP_LAST writers may wait for a heartbeat period.)
  bool wait_rows(const std::string& file, std::size_t rows, std::chrono::seconds limit = 15s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      try {
        if (causal::io::parse_csv(slurp(dir_ / "run" / file)).rows.size() >= rows) return true;
      } catch (const std::runtime_error&) {
        // a row being written right now: look again
      }
      std::this_thread::sleep_for(50ms);
    }
    return false;
  }

  // The rms condition vector of snapshot n (three channels).
  causal_twin::ConditionVector condition_vector(std::uint64_t n) const {
    causal_twin::ConditionVector c;
    c.asset_group(asset_);
    c.feature("rms");
    c.snapshot_index(n);
    c.time_ns(kT0 + static_cast<std::int64_t>(n) * kDt);
    c.channel_names({channel(1), channel(2), channel(3)});
    c.values({feature_value(n, 1), feature_value(n, 2), feature_value(n, 3)});
    return c;
  }

  // A RAISED alarm "<asset>/<channel>/<kind>/1" of this test's asset at snapshot `index`.
  causal_twin::Alarm raised_alarm(int ch, const std::string& kind, causal_twin::Severity severity,
                                  std::uint64_t index) const {
    causal_twin::Alarm a;
    a.alarm_id(asset_ + "/" + std::to_string(ch) + "/" + kind + "/1");
    a.asset_group(asset_);
    a.channel(static_cast<std::uint16_t>(ch));
    a.channel_name(channel(ch));
    a.kind(kind);
    a.severity(severity);
    a.state(causal_twin::RAISED);
    a.raised_time_ns(kT0 + static_cast<std::int64_t>(index) * kDt);
    a.sample_index(index);
    return a;
  }

  void publish_alarm(causal_twin::Alarm& a) {
    ASSERT_EQ(writers_->alarms.write(a, stop_), causal::dds::WriteResult::Ok);
    // KEEP_LAST 1 per alarm id: the recorder must have this state before the next one replaces it.
    ASSERT_TRUE(wait_rows("alarms.csv", ++alarms_sent_)) << slurp(dir_ / "recorder.log");
  }

  fs::path dir_;
  std::string asset_, file_asset_;
  std::vector<pid_t> children_;
  std::atomic<bool> stop_{false};
  std::unique_ptr<causal::dds::Participant> participant_;
  std::unique_ptr<Writers> writers_;
  std::size_t alarms_sent_ = 0;
};

TEST_F(RecorderIntegration, RecordsEveryTopicAndTheReportRendersIt) {
  const pid_t recorder = start_recorder(161, {"--idle-exit", "1.5"});
  ASSERT_GT(recorder, 0);
  open_publisher(161);
  if (HasFatalFailure()) return;

  // Condition vectors and condition-level factors, outcomes interleaved differently at every index.
  for (std::uint64_t n = 0; n < kSnapshots; ++n) {
    causal_twin::ConditionVector c = condition_vector(n);
    c.discontinuity(n == 0);
    ASSERT_EQ(writers_->conditions.write(c, stop_), causal::dds::WriteResult::Ok);
    for (int i = 0; i < kG; ++i) {
      const int k = 1 + static_cast<int>((n + static_cast<std::uint64_t>(i)) % kG);
      publish(factors(n, k, causal_twin::FILTER));
      if (n + 2 < kSnapshots) publish(factors(n, k, causal_twin::FIXED_LAG_SMOOTHER));
    }
  }
  for (int k = 1; k <= kG; ++k) publish(factors(0, k, causal_twin::FILTER, causal_twin::SAMPLE_LEVEL));
  ASSERT_TRUE(wait_rows("conditions_" + file_asset_ + "_rms.csv", kSnapshots)) << slurp(dir_ / "recorder.log");
  ASSERT_TRUE(wait_rows("factors_" + file_asset_ + "_condition_filter.csv", kSnapshots));
  ASSERT_TRUE(wait_rows("factors_" + file_asset_ + "_condition_fixed-lag.csv", kSnapshots - 2));

  causal_twin::Alarm a = raised_alarm(2, "feature_drift", causal_twin::WARNING, 4);
  a.root_cause_channel(3);
  a.root_cause_name(channel(3));
  a.score(9.5);
  a.threshold(5.0);
  a.reason("rms of Bearing 2 rose, \"sharply\"");
  a.category("degradation");
  a.root_cause_confidence(0.5);
  publish_alarm(a);
  a.state(causal_twin::ESCALATED);
  a.severity(causal_twin::CRITICAL);
  a.sample_index(7);
  publish_alarm(a);
  a.state(causal_twin::CLEARED);
  a.sample_index(10);
  a.cleared_time_ns(kT0 + 10 * kDt);
  publish_alarm(a);
  causal_twin::Alarm b = raised_alarm(3, "innovation_nis", causal_twin::ADVISORY, 6);
  publish_alarm(b);
  causal_twin::Recommendation r;
  r.recommendation_id(a.alarm_id() + "/1");
  r.alarm_id(a.alarm_id());
  r.asset_group(asset_);
  r.rank(1);
  r.target_channel(2);
  r.intervene_channel(3);
  r.delta(-0.1);
  r.confidence(0.9);
  r.text("lower Bearing 3's load, then re-check");
  ASSERT_EQ(writers_->recommendations.write(r, stop_), causal::dds::WriteResult::Ok);
  ASSERT_TRUE(wait_rows("recommendations.csv", 1));

  writers_.reset();  // the publishers leave: the recorder exits once they are gone and it is idle
  ASSERT_EQ(wait_exit(recorder, 30s), 0) << slurp(dir_ / "recorder.log");
  const std::string log = slurp(dir_ / "recorder.log");
  EXPECT_NE(log.find("rows written:"), std::string::npos) << log;
  const fs::path run = dir_ / "run";

  // Conditions: exact header, every value read back bit for bit.
  const auto cond = lines_of(run / ("conditions_" + file_asset_ + "_rms.csv"));
  ASSERT_EQ(cond.size(), 1 + kSnapshots) << log;
  EXPECT_EQ(cond[0], "snapshot,time_ns,time_utc,Bearing 1,Bearing 2,Bearing 3");
  for (std::uint64_t n = 0; n < kSnapshots; ++n) {
    const auto cells = split(cond[1 + n]);
    ASSERT_EQ(cells.size(), 6u);
    EXPECT_EQ(cells[0], std::to_string(n));
    EXPECT_EQ(cells[1], std::to_string(kT0 + static_cast<std::int64_t>(n) * kDt));
    for (int c = 1; c <= kG; ++c) EXPECT_EQ(std::strtod(cells[2 + c].c_str(), nullptr), feature_value(n, c));
  }
  EXPECT_EQ(split(cond[1])[2], "2004-02-12 10:32:39");

  // Factors: one row per index assembled from the three outcome messages, outcome-major.
  std::string header = "index,time_ns,time_utc";
  for (int k = 1; k <= kG; ++k) for (const auto& n : names_of(k)) header += "," + n;
  for (int k = 1; k <= kG; ++k) for (const auto& n : names_of(k)) header += ",sd_" + n;
  for (int k = 1; k <= kG; ++k) header += ",nis_" + channel(k);
  for (const bool smoothed : {false, true}) {
    const auto f = lines_of(run / ("factors_" + file_asset_ + "_condition_" + (smoothed ? "fixed-lag" : "filter") + ".csv"));
    const std::uint64_t rows = smoothed ? kSnapshots - 2 : kSnapshots;
    ASSERT_EQ(f.size(), 1 + rows);
    EXPECT_EQ(f[0], header);
    const std::size_t per = names_of(1).size();
    for (std::uint64_t n = 0; n < rows; ++n) {
      const auto cells = split(f[1 + n]);
      ASSERT_EQ(cells.size(), 3 + 2 * per * kG + kG);
      EXPECT_EQ(cells[0], std::to_string(n));
      for (int k = 1; k <= kG; ++k) {
        for (std::size_t i = 0; i < per; ++i) {
          const std::size_t col = 3 + (static_cast<std::size_t>(k) - 1) * per + i;
          EXPECT_EQ(std::strtod(cells[col].c_str(), nullptr), factor_value(n, k, i, smoothed));
          EXPECT_EQ(std::strtod(cells[col + per * kG].c_str(), nullptr), factor_sd(n, k, i));
        }
        EXPECT_EQ(std::strtod(cells[3 + 2 * per * kG + static_cast<std::size_t>(k) - 1].c_str(), nullptr), 1.0 + 0.1 * k);
      }
    }
  }
  EXPECT_FALSE(fs::exists(run / ("factors_" + file_asset_ + "_sample_filter.csv")));  // no --sample-level

  // Alarms: one row per state change, text quoted, the escalation placed at snapshot 7's time.
  const std::string alarms = slurp(run / "alarms.csv");
  const auto alarm_rows = causal::io::parse_csv(alarms).rows;
  ASSERT_EQ(alarm_rows.size(), 4u) << alarms;
  // ... then the decision fields: no next level on this message, so empty cells.
  EXPECT_NE(alarms.find(",\"rms of Bearing 2 rose, \"\"sharply\"\"\",degradation,0.5,,,,\n"), std::string::npos) << alarms;
  EXPECT_EQ(alarm_rows[0][1], "raised");
  EXPECT_EQ(alarm_rows[0][2], "warning");
  EXPECT_EQ(alarm_rows[0][8], "2004-02-12 11:12:39");
  EXPECT_EQ(alarm_rows[1][1], "escalated");
  EXPECT_EQ(alarm_rows[1][8], "2004-02-12 11:42:39");
  EXPECT_EQ(alarm_rows[2][1], "cleared");
  EXPECT_EQ(alarm_rows[2][10], "2004-02-12 12:12:39");
  EXPECT_EQ(alarm_rows[2][12], "Bearing 3");
  EXPECT_EQ(alarm_rows[3][3], "innovation_nis");
  const auto rec = causal::io::parse_csv(slurp(run / "recommendations.csv"));
  ASSERT_EQ(rec.rows.size(), 1u);
  EXPECT_EQ(rec.header.size(), 34u);  // 26 + sample_index, action, action_kind, act_on_*, horizon_hours, order_*
  EXPECT_EQ(rec.rows[0][12], "lower Bearing 3's load, then re-check");

  // The report, when gnuplot is there.
  const fs::path report = dir_ / "report";
  if (!on_path("gnuplot")) {
    EXPECT_EQ(run_sync({CAUSAL_REPORT_BIN, "--run", run.string(), "--out", report.string()}, dir_ / "report.log"), 2);
    GTEST_SKIP() << "gnuplot is not installed: CSV checks passed, PNG rendering skipped";
  }
  ASSERT_EQ(run_sync({CAUSAL_REPORT_BIN, "--run", run.string(), "--out", report.string()}, dir_ / "report.log"), 0)
      << slurp(dir_ / "report.log");
  std::vector<std::string> pngs{"condition_trends_" + file_asset_, "alarm_timeline_" + file_asset_,
                                "causal_graph_" + file_asset_};
  for (int k = 1; k <= kG; ++k) {  // channel names in file names: the one sanitiser, as the asset group's
    pngs.push_back("factors_" + file_asset_ + "_" + causal::io::safe_file_component("Bearing " + std::to_string(k)));
  }
  for (const auto& stem : pngs) {
    const std::string png = slurp(report / (stem + ".png"));
    ASSERT_GT(png.size(), 1000u) << stem;
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << stem;
  }
  const std::string md = slurp(report / ("report_" + file_asset_ + ".md"));
  EXPECT_NE(md.find("(alarm_timeline_" + file_asset_ + ".png)"), std::string::npos) << md;
  EXPECT_NE(md.find("| Bearing 2 | 2004-02-12 11:12:39 | warning (escalated to critical) | feature_drift | Bearing 3 | "
                    "2004-02-12 12:12:39 |"),
            std::string::npos)
      << md;
}

TEST_F(RecorderIntegration, SigtermRecordsWhatArrivedIncludingPartialRows) {
  const pid_t recorder = start_recorder(162, {});
  ASSERT_GT(recorder, 0);
  open_publisher(162);
  if (HasFatalFailure()) return;
  publish(factors(1, 1, causal_twin::FILTER));
  publish(factors(1, 3, causal_twin::FILTER));  // outcome 2 of index 1 never comes
  for (int k = 1; k <= kG; ++k) publish(factors(0, k, causal_twin::FILTER));
  // One writer delivers in order: once row 0 (sent last) is on disk, the recorder holds index 1's parts too.
  ASSERT_TRUE(wait_rows("factors_" + file_asset_ + "_condition_filter.csv", 1)) << slurp(dir_ / "recorder.log");
  ASSERT_EQ(::kill(recorder, SIGTERM), 0);
  ASSERT_EQ(wait_exit(recorder, 20s), 0) << slurp(dir_ / "recorder.log");
  const auto f = lines_of(dir_ / "run" / ("factors_" + file_asset_ + "_condition_filter.csv"));
  ASSERT_EQ(f.size(), 3u) << slurp(dir_ / "recorder.log");
  const std::size_t per = names_of(1).size();
  const auto partial = split(f[2]);
  ASSERT_EQ(partial.size(), 3 + 2 * per * kG + kG);
  EXPECT_EQ(partial[0], "1");
  for (std::size_t i = 0; i < per; ++i) {
    EXPECT_EQ(std::strtod(partial[3 + i].c_str(), nullptr), factor_value(1, 1, i, false));
    EXPECT_EQ(partial[3 + per + i], "");            // outcome 2's factors
    EXPECT_EQ(partial[3 + per * kG + per + i], "");  // and their sds
  }
  EXPECT_EQ(partial[3 + 2 * per * kG + 1], "");  // nis of outcome 2
  EXPECT_NE(slurp(dir_ / "recorder.log").find("1 partial rows"), std::string::npos);
}

// Exactly once: what an estimator restart or a replayed history sends again is counted, not written again,
// and the snapshots the recorder never got are named in its exit log.
TEST_F(RecorderIntegration, ReSentMessagesAreWrittenOnceAndGapsAreLogged) {
  const pid_t recorder = start_recorder(163, {"--idle-exit", "1.5"});
  ASSERT_GT(recorder, 0);
  open_publisher(163);
  if (HasFatalFailure()) return;
  // Condition vectors 0, 1, 3, 4 (2 never sent), then 0 and 1 again (the estimator restarted).
  for (std::uint64_t n : {0u, 1u, 3u, 4u, 0u, 1u}) {
    causal_twin::ConditionVector c = condition_vector(n);
    ASSERT_EQ(writers_->conditions.write(c, stop_), causal::dds::WriteResult::Ok);
  }
  // Factors of indices 0..2 and 4 (3 never sent), then index 1 again.
  for (std::uint64_t n : {0u, 1u, 2u, 4u, 1u}) {
    for (int k = 1; k <= kG; ++k) publish(factors(n, k, causal_twin::FILTER));
  }
  causal_twin::Alarm a = raised_alarm(1, "feature_drift", causal_twin::ADVISORY, 3);
  a.reason("drift");
  publish_alarm(a);
  // The same state again (a replayed last value): received, not written. KEEP_LAST 1 per alarm id, so it
  // must be acknowledged before the next state replaces it.
  ASSERT_EQ(writers_->alarms.write(a, stop_), causal::dds::WriteResult::Ok);
  ASSERT_TRUE(writers_->alarms.wait_for_acknowledgments(10s));
  a.state(causal_twin::ESCALATED);
  a.severity(causal_twin::WARNING);
  a.sample_index(4);
  publish_alarm(a);
  // Acknowledged by the live reader = in its history: recorded before it exits (idle exit).
  ASSERT_TRUE(writers_->conditions.wait_for_acknowledgments(10s));
  ASSERT_TRUE(writers_->factors.wait_for_acknowledgments(10s));
  writers_.reset();  // the publishers leave: the recorder exits once they are gone and it is idle
  // The recording has holes (snapshots never sent): exit code 4 says it is incomplete.
  ASSERT_EQ(wait_exit(recorder, 30s), 4) << slurp(dir_ / "recorder.log");
  const std::string log = slurp(dir_ / "recorder.log");

  const auto cond = lines_of(dir_ / "run" / ("conditions_" + file_asset_ + "_rms.csv"));
  ASSERT_EQ(cond.size(), 5u) << log;
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(split(cond[i + 1])[0], std::to_string(std::vector<int>{0, 1, 3, 4}[i]));
  const auto f = lines_of(dir_ / "run" / ("factors_" + file_asset_ + "_condition_filter.csv"));
  ASSERT_EQ(f.size(), 5u) << log;
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(split(f[i + 1])[0], std::to_string(std::vector<int>{0, 1, 2, 4}[i]));
  EXPECT_EQ(lines_of(dir_ / "run" / "alarms.csv").size(), 3u) << log;

  EXPECT_NE(log.find("condition vectors conditions_" + file_asset_ +
                     "_rms.csv: received 6, written 4, duplicates 2, refused 0; lost snapshots 2"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("causal factors factors_" + file_asset_ +
                     "_condition_filter.csv: received 15 messages (15 outcome vectors), duplicates 3, refused 0 outcome "
                     "vectors; 4 rows written; "
                     "lost snapshots 3"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("alarms: received 3, written 2, duplicates 1, refused 0"), std::string::npos) << log;
}

TEST(ReportErrors, MissingInputsExitWithCodeTwoAndSayWhat) {
  const fs::path dir = fs::temp_directory_path() / ("causal_report_err_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "empty");
  auto run = [&](const std::vector<std::string>& args, std::string& output) {
    std::string cmd = CAUSAL_REPORT_BIN;
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " > '" + (dir / "out.log").string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    output = slurp(dir / "out.log");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  std::string out;
  EXPECT_EQ(run({"--run", (dir / "missing").string(), "--out", (dir / "o").string()}, out), 2);
  EXPECT_NE(out.find("does not exist"), std::string::npos) << out;
  EXPECT_EQ(run({"--run", (dir / "empty").string(), "--out", (dir / "o").string()}, out), 2);
  EXPECT_NE(out.find("no recorder CSV files"), std::string::npos) << out;
  std::ofstream(dir / "empty" / "conditions_a_rms.csv") << "snapshot,time_ns,time_utc,B1\n0,1,x,1\n";
  EXPECT_EQ(run({"--run", (dir / "empty").string(), "--out", (dir / "o").string(), "--gnuplot", "no-such-gnuplot"}, out), 2);
  EXPECT_NE(out.find("gnuplot not found"), std::string::npos) << out;
  EXPECT_EQ(run({"--run", (dir / "empty").string(), "--out", (dir / "o").string(), "--asset-group", "zz"}, out), 2);
  EXPECT_NE(out.find("asset 'zz' is not in"), std::string::npos) << out;
  EXPECT_NE(out.find("assets: a"), std::string::npos) << out;
  fs::remove_all(dir);
}

}  // namespace
