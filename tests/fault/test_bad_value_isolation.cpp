// Bad values are isolated ("Nothing lost, nothing stalls"): two asset groups replayed at once into one
// causal-estimator, alarm-recommender and causal-recorder over a private loopback DDS domain. Group B's feature
// table is corrupted (a 1e300, a dead channel reading 0.0 for a stretch, a channel scaled by 1e-9 for a
// stretch) and one of its vectors carries a NaN; group A's is the shipped table.
// sensor-replay refuses a table with a non-finite cell as a whole (io::read_feature_table: "non-finite value"),
// so the NaN cannot come from a file: group B is replayed in two pieces (rows 0..299, then 300 + 1..983) and
// this test publishes row 300 itself, with NaN in bearing 2, between them, on the same topic and key, as a
// faulty sensor would. (The second piece starts with a discontinuity flag, which only group B sees.)
//
// Independent truth for group A: a run of group A alone with the same settings. Its recording (condition
// vectors, condition-level factors, alarms) must be byte-identical with B beside it. Truth for group B: the
// corruptions this test wrote, and the input screen's documented thresholds (common/pipeline/input_screen.hpp,
// InputScreenParams::for_conditions): |x| > 1e6 is out_of_range, NaN is non_finite, 10 identical vectors in a
// row quarantine a channel (stuck), a block of 10 vectors whose median |x| is below 1e-3 x the channel's
// reference quarantines it (scale_change). Alarm ids are "<group>/<channel>/<kind>/s<snapshot>"
// (services/causal_estimator/data_quality_alarms.hpp). Bad values are screened, not refused, so every service
// exits 0 (the estimator's code 4 is for data lost or refused).
#include "dds_observer.hpp"
#include "fault_run_support.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/io/feature_table.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <cstdio>
#include <set>

namespace ft = causal::test::fault;
using causal::test::ServiceProcess;

namespace {

constexpr std::size_t kSnapshots = 984;
const std::string kGroupA = "shaft-a";
const std::string kGroupB = "shaft-b";

// Where group B's table is corrupted (rows = snapshot indices), all inside the monitored part of the run.
constexpr std::size_t kHugeRow = 200;                 // bearing1 = 1e300
constexpr std::size_t kNanRow = 300;                  // bearing2 = NaN
constexpr std::size_t kDeadFirst = 400, kDeadEnd = 450;   // bearing3 = 0.0 (50 snapshots)
constexpr std::size_t kTinyFirst = 600, kTinyEnd = 700;   // bearing4 x 1e-9 (100 snapshots)

// Writes a copy of the shipped table with group B's corruptions in the _meanabs columns; the other columns
// are left as they are (the replay does not read them).
void write_corrupted_table(const ft::fs::path& out_path) {
  std::ifstream in(ft::feature_table());
  std::ofstream out(out_path);
  std::string line;
  std::getline(in, line);
  out << line << '\n';
  const auto header = ft::split_csv(line);
  auto col = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    throw std::runtime_error("no column " + name);
  };
  const std::size_t b1 = col("bearing1_meanabs"), b3 = col("bearing3_meanabs"),
                    b4 = col("bearing4_meanabs");
  for (std::size_t row = 0; std::getline(in, line); ++row) {
    auto cells = ft::split_csv(line);
    if (row == kHugeRow) cells[b1] = "1e300";
    if (row >= kDeadFirst && row < kDeadEnd) cells[b3] = "0.0";
    if (row >= kTinyFirst && row < kTinyEnd) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", std::stod(cells[b4]) * 1e-9);
      cells[b4] = buf;
    }
    for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
    out << '\n';
  }
}

// Publishes row `row` of `table` as group B's condition vector with NaN in bearing 2, once the estimator reads
// the topic, and waits for its acknowledgement (so the next piece of the replay comes after it).
bool publish_nan_vector(int domain, const std::string& table, std::size_t row) {
  causal::dds::DdsSettings settings;
  settings.profile_files = {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml", ft::transport()};
  settings.domain_id = domain;
  settings.participant_name = "fault-test-faulty-sensor";
  causal::dds::Participant participant(settings);
  causal::dds::TypedWriter<causal_twin::ConditionVectorPubSubType> writer(
      participant, causal::dds::topics::kConditionInput, causal::dds::profiles::kConditionInputWriter);
  std::atomic<bool> never{false};
  if (!writer.wait_for_named_readers("causal-estimator", 1, std::chrono::seconds(60), never)) return false;
  const causal::io::FeatureTable t = causal::io::read_feature_table(table, "_meanabs");
  Eigen::VectorXd values = t.values.row(static_cast<Eigen::Index>(row)).transpose();
  values[1] = std::numeric_limits<double>::quiet_NaN();
  const causal::dds::ConditionHeader header{kGroupB, "meanabs", row, t.time_ns.at(row),
                                            {"bearing1", "bearing2", "bearing3", "bearing4"}, false};
  causal_twin::ConditionVector msg;
  causal::dds::to_condition_vector(header, values, msg);
  return writer.write(msg, never) == causal::dds::WriteResult::Ok &&
         writer.wait_for_acknowledgments(std::chrono::seconds(30));
}

struct RunResult {
  int recorder = -1, recommender = -1, estimator = -1;
  std::vector<int> replays;
  std::string estimator_log, recorder_log, recommender_log;
};

// One run: recorder, recommender, estimator, then one sensor-replay per (group, table), as fast as possible.
// One replay of a table as an asset group: all of it, or rows [first, first + count).
struct ReplaySpec {
  std::string group, table;
  std::size_t first = 0, count = 0;
};

// One run: recorder, recommender, estimator, then the replays of `parallel` (at once, as fast as possible)
// and, if given, group B's staged input (`staged_b`: replay rows 0..299, publish the NaN row, replay the rest).
RunResult run_services(const ft::fs::path& dir, int domain, const std::vector<ReplaySpec>& parallel,
                       const std::string& staged_b = "") {
  const std::string d = std::to_string(domain);
  const std::vector<std::string> common = {"--domain", d, "--transport", ft::transport()};
  auto with = [&](std::vector<std::string> head, const std::vector<std::string>& tail) {
    head.insert(head.begin() + 1, common.begin(), common.end());
    head.insert(head.end(), tail.begin(), tail.end());
    return head;
  };
  ServiceProcess recorder("causal-recorder",
                          with({CAUSAL_RECORDER_BIN}, {"--out", (dir / "rec").string(), "--idle-exit", "6", "--max-runtime", "200"}),
                          (dir / "recorder.log").string());
  ServiceProcess recommender("alarm-recommender", with({ALARM_RECOMMENDER_BIN}, {"--idle-exit", "5", "--max-runtime", "200"}),
                             (dir / "recommender.log").string());
  // Idle exits longer than launch.sh's: group B's input pauses between its pieces.
  ServiceProcess estimator("causal-estimator",
                           with({CAUSAL_ESTIMATOR_BIN}, {"--idle-exit", "10", "--max-runtime", "200", "--wait-for",
                                                         "alarm-recommender", "causal-recorder", "--wait-timeout", "60"}),
                           (dir / "estimator.log").string());
  auto replay = [&](const ReplaySpec& spec, const std::string& log) {
    return std::make_unique<ServiceProcess>(
        "sensor-replay",
        with({SENSOR_REPLAY_BIN}, {"--features", spec.table, "--feature-suffix", "_meanabs", "--feature-name", "meanabs",
                                   "--channel-names", "bearing1", "bearing2", "bearing3", "bearing4", "--asset-group",
                                   spec.group, "--first-snapshot", std::to_string(spec.first), "--max-snapshots",
                                   std::to_string(spec.count), "--speed", "0", "--wait-for", "causal-estimator",
                                   "--wait-timeout", "60"}),
        (dir / log).string());
  };
  std::vector<std::unique_ptr<ServiceProcess>> replays;
  for (const auto& spec : parallel) replays.push_back(replay(spec, "replay_" + spec.group + ".log"));
  RunResult r;
  if (!staged_b.empty()) {
    auto first = replay({kGroupB, staged_b, 0, kNanRow}, "replay_b_first.log");
    r.replays.push_back(first->wait(std::chrono::seconds(150)).value_or(-1));
    EXPECT_TRUE(publish_nan_vector(domain, staged_b, kNanRow)) << "the NaN vector of group B was not delivered";
    auto rest = replay({kGroupB, staged_b, kNanRow + 1, 0}, "replay_b_rest.log");
    r.replays.push_back(rest->wait(std::chrono::seconds(150)).value_or(-1));
  }
  for (auto& p : replays) r.replays.push_back(p->wait(std::chrono::seconds(150)).value_or(-1));
  r.estimator = estimator.wait(std::chrono::seconds(60)).value_or(-1);
  r.recommender = recommender.wait(std::chrono::seconds(60)).value_or(-1);
  r.recorder = recorder.wait(std::chrono::seconds(60)).value_or(-1);
  r.estimator_log = estimator.output();
  r.recorder_log = recorder.output();
  r.recommender_log = recommender.output();
  return r;
}

void expect_all_exit_zero(const RunResult& r, const std::string& run) {
  for (std::size_t i = 0; i < r.replays.size(); ++i) EXPECT_EQ(r.replays[i], 0) << run << ": sensor-replay " << i;
  EXPECT_EQ(r.estimator, 0) << run << ": screened values are not refused data\n" << r.estimator_log;
  EXPECT_EQ(r.recommender, 0) << run << "\n" << r.recommender_log;
  EXPECT_EQ(r.recorder, 0) << run << "\n" << r.recorder_log;
}

}  // namespace

TEST(BadValueIsolation, CorruptedGroupLeavesTheOtherByteIdenticalAndRaisesDataQualityAlarms) {
  const ft::fs::path work = ft::work_dir("isolation");
  const ft::fs::path bad_table = work / "group_b_corrupted.csv";
  write_corrupted_table(bad_table);
  ft::fs::create_directories(work / "alone");
  ft::fs::create_directories(work / "both");

  const RunResult alone = run_services(work / "alone", ft::domain_id(6), {{kGroupA, ft::feature_table()}});
  expect_all_exit_zero(alone, "group A alone");
  // A reader in this process as well: the recording has no category column, the Alarm messages do.
  causal::test::DdsObserver observer(ft::domain_id(7));
  const RunResult both =
      run_services(work / "both", ft::domain_id(7), {{kGroupA, ft::feature_table()}}, bad_table.string());
  expect_all_exit_zero(both, "groups A and B");

  // No restart and no checkpoint here: an input skipped as "processed before a restart" is an input lost (a
  // vector delivered after a later one of its asset group; the recorder then reports the gap).
  for (const RunResult* r : {&alone, &both}) {
    EXPECT_EQ(r->estimator_log.find("inputs processed before a restart skipped"), std::string::npos)
        << ft::grab_last(r->estimator_log, R"((asset '[^\n]*skipped))") << "\n"
        << ft::grab_last(r->recorder_log, R"((condition vectors [^\n]*lost snapshots[^\n]*))");
  }

  // Group A: every recorded file byte-identical, and complete (0..983 once each).
  const auto rec_alone = work / "alone" / "rec", rec_both = work / "both" / "rec";
  const std::string cond = "conditions_" + kGroupA + "_meanabs.csv";
  const std::string cond_alone = ft::read_text(rec_alone / cond);
  EXPECT_EQ(ft::read_csv(rec_alone / cond).rows.size(), kSnapshots);
  EXPECT_TRUE(cond_alone == ft::read_text(rec_both / cond)) << cond << " differs with group B beside it";
  const auto factors_alone = ft::condition_factor_files(rec_alone, kGroupA);
  const auto factors_both = ft::condition_factor_files(rec_both, kGroupA);
  EXPECT_EQ(factors_alone.size(), 2u) << "condition-level filter and fixed-lag tables";
  ASSERT_EQ(factors_alone.size(), factors_both.size());
  for (const auto& [name, path] : factors_alone) {
    EXPECT_EQ(ft::read_csv(path).rows.size(), kSnapshots) << name;
    EXPECT_TRUE(ft::read_text(path) == ft::read_text(factors_both.at(name))) << name << " differs with group B beside it";
  }
  const auto alarms_alone = ft::alarm_histories(ft::read_csv(rec_alone / "alarms.csv"), kGroupA);
  const auto alarms_both = ft::alarm_histories(ft::read_csv(rec_both / "alarms.csv"), kGroupA);
  EXPECT_FALSE(alarms_alone.empty()) << "IMS test 2 raises alarms on bearing 1 from snapshot 533";
  ASSERT_EQ(alarms_alone.size(), alarms_both.size()) << "alone:\n" << ft::describe(alarms_alone) << "both:\n"
                                                     << ft::describe(alarms_both);
  for (const auto& [id, h] : alarms_alone) {
    ASSERT_EQ(alarms_both.count(id), 1u) << id;
    EXPECT_EQ(h.lines, alarms_both.at(id).lines) << "recorded rows of alarm " << id << " differ";
  }
  for (const auto& [id, h] : alarms_both) {
    EXPECT_TRUE(h.kind != "non_finite" && h.kind != "out_of_range" && h.kind != "channel_quarantined")
        << "data-quality alarm on group A: " << id;
  }
  std::size_t a_rows = 0;
  for (const auto& [id, h] : alarms_alone) a_rows += h.lines.size();

  // Group B: recorded in full as well (bad values are recorded as sent), and its data-quality alarms.
  const auto cond_b = ft::read_csv(rec_both / ("conditions_" + kGroupB + "_meanabs.csv"));
  EXPECT_EQ(cond_b.rows.size(), kSnapshots) << "group B's condition vectors recorded";
  const auto factors_b = ft::condition_factor_files(rec_both, kGroupB);
  for (const auto& [name, path] : factors_b) EXPECT_EQ(ft::read_csv(path).rows.size(), kSnapshots) << name;
  const ft::CsvTable all_alarms = ft::read_csv(rec_both / "alarms.csv");
  const auto alarms_b = ft::alarm_histories(all_alarms, kGroupB);
  std::set<std::string> quality_raised;  // the alarms.csv has no category column: data-quality kinds
  for (const auto& [id, h] : alarms_b) {
    if (h.kind == "non_finite" || h.kind == "out_of_range" || h.kind == "channel_quarantined") quality_raised.insert(id);
  }
  // Snapshot of the verdict: first bad value for bad values; for a dead channel the 10th identical value;
  // for the scaled one the end of the first block of 10 (blocks counted from snapshot 0) inside the stretch.
  const std::vector<std::string> expected = {
      kGroupB + "/bearing1/out_of_range/s" + std::to_string(kHugeRow),
      kGroupB + "/bearing2/non_finite/s" + std::to_string(kNanRow),
      kGroupB + "/bearing3/channel_quarantined/s" + std::to_string(kDeadFirst + 9),
      kGroupB + "/bearing4/channel_quarantined/s" + std::to_string(kTinyFirst + 9),
  };
  for (const auto& id : expected) {
    EXPECT_EQ(quality_raised.count(id), 1u) << "missing data-quality alarm " << id << "; group B's alarms:\n"
                                            << ft::describe(alarms_b);
  }
  EXPECT_EQ(quality_raised.size(), expected.size()) << ft::describe(alarms_b);
  std::set<std::string> categorised;  // raised with Alarm.category "data_quality", as they crossed the wire
  for (const auto& a : observer.alarms()) {
    if (a.category() == "data_quality" && a.state() == causal_twin::RAISED) categorised.insert(a.alarm_id());
  }
  EXPECT_EQ(categorised, std::set<std::string>(expected.begin(), expected.end()));
  // The bad-value alarms clear at the next clean snapshot (the first one after the bad value).
  for (std::size_t i = 0; i < 2; ++i) {
    const auto it = alarms_b.find(expected[i]);
    if (it == alarms_b.end()) continue;
    const std::size_t row = i == 0 ? kHugeRow : kNanRow;
    EXPECT_EQ(it->second.events, (std::vector<std::string>{"raised/advisory/" + std::to_string(row),
                                                           "cleared/advisory/" + std::to_string(row + 1)}))
        << expected[i];
  }

  std::printf("[ fault    ] group A alone: %zu condition rows, %zu factor tables, %zu alarm ids (%zu rows); with B "
              "beside it: byte-identical %s\n",
              ft::read_csv(rec_alone / cond).rows.size(), factors_alone.size(), alarms_alone.size(), a_rows,
              HasFailure() ? "NO" : "yes");
  std::printf("[ fault    ] group B: %zu condition rows recorded, %zu alarm ids, data-quality alarms:", cond_b.rows.size(),
              alarms_b.size());
  for (const auto& id : quality_raised) std::printf(" %s", id.c_str());
  std::printf("\n[ fault    ] exit codes (A+B run): replay B 0..299 %d, replay B 301..983 %d, replay A %d, estimator %d, "
              "recommender %d, recorder %d\n",
              both.replays.at(0), both.replays.at(1), both.replays.at(2), both.estimator, both.recommender, both.recorder);
  std::printf("[ fault    ] estimator (A+B): %s\n", ft::grab(both.estimator_log, R"((causal-estimator: received [^\n]*))").c_str());
  std::printf("[ fault    ] recorder (A+B): %s\n", ft::grab(both.recorder_log, R"((rows written: [^\n]*))").c_str());

  if (!HasFailure()) ft::fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
