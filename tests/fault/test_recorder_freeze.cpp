// Delivery contract, frozen consumer: causal-recorder is stopped (SIGSTOP) for 30 s in the middle of the
// paced 984-row feature replay (IMS test 2, mean |x| per snapshot). A frozen reader must not stall the
// producers: its participant lease (5 s) expires, it is unmatched, and the estimator carries on. Every
// other consumer (alarm-recommender, a reader in this process) gets every condition vector exactly once,
// and after SIGCONT the recorder states exactly what it missed.
//
// Expectations come from the set-up: 984 rows in the table (read here), G = 4 outcomes per snapshot, the
// pacing (speed x plant time), the lease in deploy/dds/localhost.xml (5 s).
#include "loopback_settings.hpp"
#include "delivery_checks.hpp"
#include "ims_feature_replay.hpp"
#include "process_runner.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/io/feature_table.hpp"
#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>
#include <regex>
#include <thread>

namespace fs = std::filesystem;
using causal::test::ims_feature_replay_argv;
using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kOutcomes = 4;
constexpr double kLeaseSeconds = 5.0;       // deploy/dds/localhost.xml leaseDuration
constexpr double kGapMarginSeconds = 3.0;   // discovery and the outbound queue catching up
constexpr double kSpeed = 12000.0;          // 983 x 600 s / 12000 = 49.2 s: outlasts the 30 s freeze
constexpr auto kFreeze = std::chrono::seconds(30);
constexpr std::size_t kFreezeAfter = 150;   // condition vectors seen here before the freeze (~6 s in)
const char* const kReaderName = "delivery-test-reader";

// The live consumer in this process: every condition vector with its arrival time, and the condition-level
// factor messages per kind. It reads causal factors too, so the estimator can wait for it by name.
class ConditionArrivals {
 public:
  explicit ConditionArrivals(int domain_id)
      : participant_(settings(domain_id)),
        conditions_(participant_, causal::dds::topics::kConditionVector, causal::dds::profiles::kConditionVectorReader),
        factors_(participant_, causal::dds::topics::kCausalFactors, causal::dds::profiles::kCausalFactorsReader) {
    loop_.attach(conditions_.get());
    loop_.attach(factors_.get());
    thread_ = std::thread([this] {
      while (loop_.wait(std::chrono::milliseconds(20))) {
        conditions_.take_all([this](const causal_twin::ConditionVector& c, const auto&) {
          std::lock_guard<std::mutex> lock(mutex_);
          arrivals_.push_back({c.snapshot_index(), Clock::now()});
        });
        factors_.take_all([this](const causal_twin::CausalFactorBatch& f, const auto&) {
          if (f.time_scale() != causal_twin::CONDITION_LEVEL) return;
          std::lock_guard<std::mutex> lock(mutex_);
          ++(f.kind() == causal_twin::FILTER ? filter_msgs_ : smoother_msgs_);
          blocks_ += f.outcomes().size();
        });
      }
    });
  }
  ~ConditionArrivals() {
    loop_.stop();
    thread_.join();
  }
  struct Arrival {
    std::uint64_t index;
    Clock::time_point at;
  };
  std::vector<Arrival> arrivals() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return arrivals_;
  }
  std::size_t count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return arrivals_.size();
  }
  std::pair<std::size_t, std::size_t> factor_messages() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return {filter_msgs_, smoother_msgs_};
  }
  std::size_t outcome_blocks() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return blocks_;
  }

 private:
  static causal::dds::DdsSettings settings(int domain_id) {
    return causal::test::loopback_settings(domain_id, kReaderName);
  }
  causal::dds::Participant participant_;
  causal::dds::TypedReader<causal_twin::ConditionVectorPubSubType> conditions_;
  causal::dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> factors_;
  causal::dds::EventLoop loop_;  // after the readers: detaches them first
  std::thread thread_;
  mutable std::mutex mutex_;
  std::vector<Arrival> arrivals_;
  std::size_t filter_msgs_ = 0, smoother_msgs_ = 0;  // condition-level batches (all outcomes of one snapshot)
  std::size_t blocks_ = 0;
};

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// The recorder's "summary topic=TOPIC file=F written=W" line's W (the file= field ends summary_count's pairs).
std::optional<std::uint64_t> recorder_written(const std::string& rec_log, const std::string& topic) {
  const std::regex line("summary topic=" + topic + R"( file=\S+ written=(\d+))");
  std::smatch m;
  if (!std::regex_search(rec_log, m, line)) return std::nullopt;
  return std::stoull(m[1]);
}

// The recorder's "recording incomplete: N sample(s) of TOPIC published while ..." lines, summed over writers.
std::uint64_t samples_named_missed(const std::string& rec_log, const std::string& topic) {
  const std::string tail = " sample(s) of " + topic + " published while";
  const std::string head = "recording incomplete: ";
  std::uint64_t total = 0;
  for (auto at = rec_log.find(tail); at != std::string::npos; at = rec_log.find(tail, at + 1)) {
    const auto start = rec_log.rfind(head, at);
    if (start == std::string::npos) continue;
    total += std::stoull(rec_log.substr(start + head.size(), at - start - head.size()));
  }
  return total;
}

// True once kFreezeAfter condition vectors reached the test reader (the stream flows), false after 60 s or when the
// replay ended first.
bool wait_for_flow(const ConditionArrivals& reader, ServiceProcess& replay) {
  const auto flowing_by = Clock::now() + std::chrono::seconds(60);
  while (reader.count() < kFreezeAfter && Clock::now() < flowing_by && replay.running()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return reader.count() >= kFreezeAfter;
}

}  // namespace

TEST(RecorderFreeze, ProducersNeverStallAndTheRecorderStatesWhatItLost) {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const auto features = causal::io::read_feature_table(table, "_meanabs");
  const std::uint64_t rows = features.time_ns.size();
  ASSERT_EQ(rows, 984u);
  const double paced_s = static_cast<double>(features.time_ns.back() - features.time_ns.front()) * 1e-9 / kSpeed;

  const fs::path work = work_dir("freeze");
  const std::string d = std::to_string(delivery_domain_id(3));
  ConditionArrivals reader(std::stoi(d));
  ServiceProcess recorder("causal-recorder",
                          {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(), "--idle-exit", "6",
                           "--max-runtime", "150"},
                          (work / "recorder.log").string());
  ServiceProcess alarm("alarm-recommender",
                       {ALARM_RECOMMENDER_BIN, "--domain", d, "--idle-exit", "5", "--max-runtime", "150"},
                       (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "4", "--max-runtime", "150",
                            "--wait-for", "alarm-recommender", "--wait-for", "causal-recorder", "--wait-for",
                            kReaderName, "--wait-timeout", "60"},
                           (work / "estimator.log").string());
  const auto replay_started = Clock::now();
  ServiceProcess replay("sensor-replay",
                        ims_feature_replay_argv(SENSOR_REPLAY_BIN, d, table, {"--speed", std::to_string(kSpeed)}),
                        (work / "replay.log").string());

  // Freeze the recorder mid-run, once the stream is flowing.
  ASSERT_TRUE(wait_for_flow(reader, replay)) << "no steady flow within 60 s:\n" << replay.output() << estimator.output();
  FrozenProcess frozen(recorder.pid());
  const auto stopped_at = Clock::now();
  ASSERT_TRUE(frozen.stopped()) << "SIGSTOP failed";
  std::this_thread::sleep_for(kFreeze);
  frozen.resume();
  const auto resumed_at = Clock::now();
  ASSERT_TRUE(replay.running()) << "the replay ended during the freeze: it must outlast it to test the recovery";

  const auto replay_code = replay.wait(std::chrono::seconds(90));
  const double replay_wall_s = seconds(Clock::now() - replay_started);
  ASSERT_TRUE(replay_code.has_value()) << "sensor-replay did not finish:\n" << replay.output();
  EXPECT_EQ(*replay_code, 0) << replay.output();
  const auto est_code = estimator.wait(std::chrono::seconds(60));
  const auto alarm_code = alarm.wait(std::chrono::seconds(60));
  const auto rec_code = recorder.wait(std::chrono::seconds(60));
  ASSERT_TRUE(est_code.has_value()) << estimator.output();
  ASSERT_TRUE(alarm_code.has_value()) << alarm.output();
  ASSERT_TRUE(rec_code.has_value()) << recorder.output();
  EXPECT_EQ(*est_code, 0) << estimator.output();
  EXPECT_EQ(*alarm_code, 0) << alarm.output();
  // The recorder lost what was published while it was frozen and unmatched: exit code 4 (an incomplete recording)
  // and the lost snapshots named, checked below.
  EXPECT_EQ(*rec_code, 4) << recorder.output();

  // 1. The producers never stalled: the live reader's largest gap while the recorder was frozen.
  const auto arrivals = reader.arrivals();
  double max_gap_s = 0.0, max_gap_all_s = 0.0;
  std::size_t during_freeze = 0;
  for (std::size_t i = 1; i < arrivals.size(); ++i) {
    const double gap = seconds(arrivals[i].at - arrivals[i - 1].at);
    max_gap_all_s = std::max(max_gap_all_s, gap);
    if (arrivals[i].at >= stopped_at && arrivals[i - 1].at <= resumed_at) max_gap_s = std::max(max_gap_s, gap);
    if (arrivals[i].at >= stopped_at && arrivals[i].at <= resumed_at) ++during_freeze;
  }
  std::printf("[ delivery ] recorder frozen %.1f s; condition vectors reaching the test reader meanwhile: %zu, "
              "largest gap during the freeze %.2f s (whole run %.2f s)\n",
              seconds(resumed_at - stopped_at), during_freeze, max_gap_s, max_gap_all_s);
  EXPECT_LE(max_gap_s, kLeaseSeconds + kGapMarginSeconds) << "the producers stalled behind the frozen recorder";

  // 2. The replay kept its pace.
  std::printf("[ delivery ] sensor-replay wall time %.2f s for a paced time of %.2f s (speed %.0f)\n", replay_wall_s,
              paced_s, kSpeed);
  EXPECT_GE(replay_wall_s, paced_s);
  EXPECT_LE(replay_wall_s, paced_s + 10.0) << "the replay was held up";

  // 3. Every condition vector reached the live reader exactly once; every factor message too.
  std::set<std::uint64_t> seen;
  std::vector<std::uint64_t> twice;
  for (const auto& a : arrivals) {
    if (!seen.insert(a.index).second) twice.push_back(a.index);
  }
  const auto [filter_msgs, smoother_msgs] = reader.factor_messages();
  std::printf("[ delivery ] test reader: %zu condition vectors (%zu distinct), %zu filter and %zu fixed-lag "
              "condition-level factor messages\n",
              arrivals.size(), seen.size(), filter_msgs, smoother_msgs);
  EXPECT_EQ(arrivals.size(), rows);
  EXPECT_EQ(seen.size(), rows);
  EXPECT_TRUE(twice.empty()) << twice.size() << " condition vectors arrived twice, the first " << twice.front();
  EXPECT_EQ(seen.empty() ? 0 : *seen.rbegin(), rows - 1);
  EXPECT_EQ(filter_msgs, rows);  // one batch per snapshot and estimator
  EXPECT_EQ(smoother_msgs, rows);
  EXPECT_EQ(reader.outcome_blocks(), 2 * rows * kOutcomes);

  // 4. The other live consumer and the producer's own counts.
  const std::string alarm_log = alarm.output(), est_log = estimator.output();
  const auto alarm_conditions = summary_count(alarm_log, "causal_twin/condition_vector", "received");
  ASSERT_TRUE(alarm_conditions.has_value()) << alarm_log;
  std::printf("[ delivery ] alarm-recommender: condition vectors received %llu\n",
              static_cast<unsigned long long>(*alarm_conditions));
  EXPECT_EQ(*alarm_conditions, rows);
  EXPECT_EQ(summary_count(est_log, "causal_twin/condition_input", "received"), std::optional<std::uint64_t>(rows));
  EXPECT_EQ(summary_count(est_log, "causal_twin/condition_vector", "sent"), std::optional<std::uint64_t>(rows));
  const auto losses = nonzero_losses(est_log + alarm_log);
  EXPECT_TRUE(losses.empty()) << "a summary reports a loss: " << losses.front();
  // The stuck reader was visible while it lasted: a HEALTH alarm raised by the estimator, and cleared.
  const auto raised = est_log.find("HEALTH RAISED causal-estimator/output/reader_not_keeping_up");
  EXPECT_NE(raised, std::string::npos) << "no HEALTH alarm for the frozen reader:\n" << est_log;
  if (raised != std::string::npos) {
    EXPECT_NE(est_log.find("HEALTH CLEARED causal-estimator/output/reader_not_keeping_up", raised), std::string::npos)
        << est_log;
  }

  // 5. The recorder states what it lost: rows written + snapshots named lost = 984, no row twice, and the
  // snapshots it names are exactly the ones missing from its file.
  const std::string rec_log = recorder.output();
  const std::string file = "conditions_ims2-shaft1_meanabs.csv";
  const RecordedFile recorded = read_recorded(work / "rec" / file);
  const RecorderConditionLine line = recorder_condition_line(rec_log, file);
  ASSERT_TRUE(recorded.exists) << rec_log;
  ASSERT_TRUE(line.found) << rec_log;
  ASSERT_FALSE(line.truncated) << "the recorder listed only part of its lost ranges:\n" << rec_log;
  std::set<std::uint64_t> absent;
  for (std::uint64_t i = 0; i < rows; ++i) {
    if (recorded.indices.count(i) == 0) absent.insert(i);
  }
  std::printf("[ delivery ] causal-recorder: rows written %llu, snapshots it names lost %zu (%s), sum %llu of %llu; "
              "received %llu, duplicates dropped %llu\n",
              static_cast<unsigned long long>(recorded.rows), line.lost.size(), ranges_text(line.lost).c_str(),
              static_cast<unsigned long long>(recorded.rows + line.lost.size()), static_cast<unsigned long long>(rows),
              static_cast<unsigned long long>(line.received), static_cast<unsigned long long>(line.duplicates));
  // Over shared memory Fast DDS 2.9 sometimes never reaches a reader again whose port stalled for 30 s (8 of 32
  // runs with four copies of this test at once: re-discovered, but nothing more from the estimator after SIGCONT
  // while alarm-recommender's alarms do arrive again, or the other way round). The recorder cannot name that tail
  // (no later index shows the gap), so it must say which writers it never heard again: exit 4 and the "recording
  // incomplete" line, naming the condition vectors' topic when their tail is what is missing, with the rows it has
  // contiguous from the first snapshot.
  if (const auto incomplete = rec_log.find("recording incomplete: this recorder did not run");
      incomplete != std::string::npos) {
    const std::string said = rec_log.substr(incomplete, rec_log.find('\n', incomplete) - incomplete);
    std::printf("[ delivery ] causal-recorder was not reached again after the freeze and says so: %llu rows, the "
                "rest named as an unrecorded tail:\n[ delivery ]   %s\n", static_cast<unsigned long long>(recorded.rows),
                said.c_str());
    EXPECT_NE(said.find("causal_twin/"), std::string::npos) << "no topic named: " << said;
    if (recorded.rows + line.lost.size() < rows) {
      EXPECT_NE(said.find(causal::dds::topics::kConditionVector), std::string::npos) << said;
    }
    EXPECT_EQ(*rec_code, 4);
    EXPECT_GE(recorded.rows, kFreezeAfter / 2) << "the rows before the freeze are missing";
    EXPECT_EQ(recorded.indices.size(), recorded.rows);
    EXPECT_TRUE(recorded.rows == 0 || *recorded.indices.rbegin() + 1 == recorded.rows + line.lost.size()) << rec_log;
    EXPECT_TRUE(recorded.repeated.empty()) << "rows recorded twice, the first " << recorded.repeated.front();
    if (!HasFailure()) fs::remove_all(work);
    causal::test::clean_stale_shared_memory();
    return;
  }
  EXPECT_EQ(recorded.rows + line.lost.size(), rows) << rec_log;
  EXPECT_TRUE(recorded.repeated.empty()) << "rows recorded twice, the first " << recorded.repeated.front();
  EXPECT_EQ(recorded.unparsable, 0u);
  EXPECT_EQ(recorded.rows, line.written);
  EXPECT_EQ(line.lost, absent) << "named lost: " << ranges_text(line.lost) << "; missing from the file: "
                               << ranges_text(absent);

  // 6. What alarm-recommender published during the freeze beyond its history rings (64 statuses per group, 64
  // updates per prognosis key) never reached the recorder, and statuses and prognoses carry no index to show it:
  // the recorder counts it by the writer's sequence numbers. Rows written + samples named missed = samples sent.
  for (const char* topic : {causal::dds::topics::kAssetStatus, causal::dds::topics::kPrognosis}) {
    const auto sent = summary_count(alarm_log, topic, "sent");
    const auto written = recorder_written(rec_log, topic);
    const std::uint64_t missed = samples_named_missed(rec_log, topic);
    ASSERT_TRUE(sent.has_value() && written.has_value()) << topic << "\n" << alarm_log << rec_log;
    std::printf("[ delivery ] %s: alarm-recommender sent %llu, causal-recorder wrote %llu and names %llu missed\n",
                topic, static_cast<unsigned long long>(*sent), static_cast<unsigned long long>(*written),
                static_cast<unsigned long long>(missed));
    EXPECT_EQ(*written + missed, *sent) << topic << "\n" << rec_log;
  }

  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

// Frozen through the end of the run: the recorder is stopped once the stream flows and resumed only after every
// publisher has finished and left. What was published meanwhile never reaches it and no later index shows the gap,
// so before, it wrote the first rows and exited 0 (a silent loss). Now it knows it did not run for longer than
// EventLoop::kSuspendedAfter and received nothing after: "recording incomplete", exit 4. Fixed DDS domain 89.
TEST(RecorderFreeze, FrozenThroughTheEndSaysTheTailIsMissing) {
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  const fs::path work = work_dir("freeze_tail");
  const std::string d = "89";
  ConditionArrivals reader(std::stoi(d));
  ServiceProcess recorder("causal-recorder",
                          {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(), "--idle-exit", "4",
                           "--max-runtime", "120"},
                          (work / "recorder.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "3", "--max-runtime", "120",
                            "--wait-for", "causal-recorder", "--wait-for", kReaderName, "--wait-timeout", "60"},
                           (work / "estimator.log").string());
  // 983 x 600 s / 40000 = 14.7 s of paced replay.
  ServiceProcess replay("sensor-replay", ims_feature_replay_argv(SENSOR_REPLAY_BIN, d, table, {"--speed", "40000"}),
                        (work / "replay.log").string());
  ASSERT_TRUE(wait_for_flow(reader, replay)) << "no steady flow within 60 s:\n" << replay.output() << estimator.output();
  FrozenProcess frozen(recorder.pid());
  ASSERT_TRUE(frozen.stopped()) << "SIGSTOP failed";
  const auto replay_code = replay.wait(std::chrono::seconds(60));
  const auto est_code = estimator.wait(std::chrono::seconds(60));
  ASSERT_TRUE(replay_code.has_value()) << replay.output();
  ASSERT_TRUE(est_code.has_value()) << estimator.output();
  EXPECT_EQ(*est_code, 0) << estimator.output();
  EXPECT_EQ(reader.count(), 984u) << "the live reader must get everything while the recorder is frozen";
  frozen.resume();
  const auto rec_code = recorder.wait(std::chrono::seconds(60));
  ASSERT_TRUE(rec_code.has_value()) << recorder.output();
  const std::string rec_log = recorder.output();
  const RecordedFile recorded = read_recorded(work / "rec" / "conditions_ims2-shaft1_meanabs.csv");
  std::printf("[ delivery ] recorder frozen until every publisher had left: %llu of 984 rows recorded, exit %d\n",
              static_cast<unsigned long long>(recorded.rows), *rec_code);
  EXPECT_LT(recorded.rows, 984u) << "the recorder was frozen before the end: it cannot have every row";
  EXPECT_EQ(*rec_code, 4) << "an incomplete recording must not exit 0:\n" << rec_log;
  EXPECT_NE(rec_log.find("did not run for"), std::string::npos) << rec_log;
  EXPECT_NE(rec_log.find("recording incomplete: this recorder did not run"), std::string::npos) << rec_log;
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
