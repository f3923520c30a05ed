// Crash safety ("Nothing lost, nothing stalls"): kill -9 of one service mid-run, restarted at once with the
// same command line, on the 984-snapshot IMS test-2 feature replay (mean |x|, paced so the kill lands mid-run),
// every service with its --state-dir where it has one. One test per victim: sensor-replay, causal-estimator,
// alarm-recommender.
//
// Independent truth: an uncrashed run with the same settings (same speed, fresh state directories) and the
// replay's own index range 0..983. Checked in the recording of causal-recorder (which is never killed):
//  * nothing lost, nothing twice, no index reset: the condition vectors and both condition-level factor tables
//    (filter, fixed lag) hold the snapshot indices 0..983 exactly once, in increasing order;
//  * the alarms (id, kind, channel, and per id its events: state, severity, snapshot index) equal the
//    uncrashed run's, every id raised once; for the recommender also: no id the first process raised is
//    raised again by the second (its id counters are in the checkpoint).
// Contract on main when written: the estimator checkpoints after every snapshot and skips input it already
// processed; the recommender checkpoints and drops re-sent observations; sensor-replay --wait-for pauses
// while the estimator is gone. Being merged: the replay rewinds to the estimator's last published snapshot + 1
// when a new estimator appears, and the estimator re-sends its recent condition-level output when a new
// reader of a named participant appears (a restarted recommender gets what it missed).
#include "fault_run_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <cstdio>
#include <optional>
#include <set>

namespace ft = causal::test::fault;
using causal::test::ServiceProcess;

namespace {

constexpr std::uint64_t kSnapshots = 984;
const std::string kGroup = "ims2-shaft1";
// 10 minutes between snapshots: x15000 is 25 snapshots per wall-clock second, ~40 s per run.
const std::string kSpeed = "15000";

enum class Victim { None, Replay, Estimator, Recommender };

struct RunOutcome {
  // Exit codes of the last process of each service (the restarted one for the victim); -1 = did not end.
  int replay = -1, estimator = -1, recommender = -1, recorder = -1;
  int killed = -1;                 // exit code of the killed process (128 + 9)
  std::string victim_first_log;    // the killed process's log
  std::string replay_log, estimator_log, recommender_log, recorder_log;
  ft::fs::path recording;
};

// The four services as deploy/launch.sh starts them, each from a factory so the victim is restarted with
// exactly the same command line (only its log file differs).
RunOutcome run_pipeline(const ft::fs::path& dir, int domain, Victim victim) {
  const std::string d = std::to_string(domain);
  auto cmd = [&](const char* bin, std::vector<std::string> args) {
    std::vector<std::string> v = {bin, "--domain", d, "--transport", ft::transport()};
    v.insert(v.end(), args.begin(), args.end());
    return v;
  };
  const auto recorder_cmd =
      cmd(CAUSAL_RECORDER_BIN, {"--out", (dir / "rec").string(), "--idle-exit", "8", "--max-runtime", "250"});
  const auto recommender_cmd = cmd(ALARM_RECOMMENDER_BIN, {"--state-dir", (dir / "alarm_state").string(), "--idle-exit",
                                                           "5", "--max-runtime", "250"});
  const auto estimator_cmd =
      cmd(CAUSAL_ESTIMATOR_BIN, {"--state-dir", (dir / "estimator_state").string(), "--idle-exit", "4", "--max-runtime",
                                 "250", "--wait-for", "alarm-recommender", "causal-recorder", "--wait-timeout", "60"});
  const auto replay_cmd = cmd(SENSOR_REPLAY_BIN, {"--features", ft::feature_table(), "--feature-suffix", "_meanabs",
                                                  "--feature-name", "meanabs", "--channel-names", "bearing1", "bearing2",
                                                  "bearing3", "bearing4", "--asset-group", kGroup, "--speed", kSpeed,
                                                  "--wait-for", "causal-estimator", "--wait-timeout", "60"});
  auto start = [&](const std::string& name, const std::vector<std::string>& argv, const std::string& log) {
    return std::make_unique<ServiceProcess>(name, argv, (dir / log).string());
  };
  auto recorder = start("causal-recorder", recorder_cmd, "recorder.log");
  auto recommender = start("alarm-recommender", recommender_cmd, "recommender.log");
  auto estimator = start("causal-estimator", estimator_cmd, "estimator.log");
  auto replay = start("sensor-replay", replay_cmd, "replay.log");

  RunOutcome out;
  out.recording = dir / "rec";
  const ft::fs::path conditions = dir / "rec" / ("conditions_" + kGroup + "_meanabs.csv");
  if (victim != Victim::None) {
    std::unique_ptr<ServiceProcess>* target = nullptr;
    std::function<bool()> due;
    std::vector<std::string> argv;
    std::string name;
    switch (victim) {
      case Victim::Replay:  // mid-run, before the first alarm
        target = &replay, argv = replay_cmd, name = "sensor-replay";
        due = [&] { return ft::recorded_rows(conditions) >= 400; };
        break;
      case Victim::Estimator:
        target = &estimator, argv = estimator_cmd, name = "causal-estimator";
        due = [&] { return ft::recorded_rows(conditions) >= 450; };
        break;
      case Victim::Recommender:  // with an alarm open: its later events must continue the same id
        target = &recommender, argv = recommender_cmd, name = "alarm-recommender";
        due = [&] { return recommender->output().find("ALARM raised") != std::string::npos; };
        break;
      case Victim::None: break;
    }
    const bool reached = ft::wait_until(due, std::chrono::seconds(150));
    EXPECT_TRUE(reached) << name << ": kill point not reached within 150 s";
    EXPECT_TRUE((*target)->running()) << name << " had already ended: the kill would not land mid-run";
    std::printf("[ fault    ] kill -9 %s at %zu recorded snapshots\n", name.c_str(), ft::recorded_rows(conditions));
    out.killed = (*target)->kill_hard();
    out.victim_first_log = (*target)->output();
    *target = start(name, argv, name + "_restarted.log");
  }
  out.replay = replay->wait(std::chrono::seconds(200)).value_or(-1);
  out.estimator = estimator->wait(std::chrono::seconds(60)).value_or(-1);
  out.recommender = recommender->wait(std::chrono::seconds(60)).value_or(-1);
  out.recorder = recorder->wait(std::chrono::seconds(60)).value_or(-1);
  out.replay_log = replay->output();
  out.estimator_log = estimator->output();
  out.recommender_log = recommender->output();
  out.recorder_log = recorder->output();
  return out;
}

// Indices 0..983, each once, in increasing order (no loss, no duplicate, no reset).
void expect_every_index_once(const ft::fs::path& file) {
  const auto idx = ft::indices(ft::read_csv(file));
  EXPECT_EQ(idx.size(), kSnapshots) << file.filename();
  std::set<std::uint64_t> unique(idx.begin(), idx.end());
  EXPECT_EQ(unique.size(), idx.size()) << file.filename() << ": an index recorded twice";
  std::vector<std::uint64_t> missing;
  for (std::uint64_t i = 0; i < kSnapshots; ++i) {
    if (unique.count(i) == 0) missing.push_back(i);
  }
  EXPECT_TRUE(missing.empty()) << file.filename() << ": " << missing.size() << " snapshots missing, first "
                               << (missing.empty() ? 0 : missing.front()) << ", last " << (missing.empty() ? 0 : missing.back());
  for (std::size_t i = 1; i < idx.size(); ++i) {
    if (idx[i] <= idx[i - 1]) {
      ADD_FAILURE() << file.filename() << ": index goes back from " << idx[i - 1] << " to " << idx[i] << " at row " << i;
      break;
    }
  }
}

std::string ids_of(const std::map<std::string, ft::AlarmHistory>& alarms) {
  std::string s;
  for (const auto& [id, h] : alarms) s += (s.empty() ? "" : " ") + id;
  return s;
}

void crash_and_compare(Victim victim, const std::string& label) {
  const ft::fs::path work = ft::work_dir("crash_" + label);
  ft::fs::create_directories(work / "reference");
  ft::fs::create_directories(work / "crashed");
  const RunOutcome ref = run_pipeline(work / "reference", ft::domain_id(6 + 2 * static_cast<int>(victim)), Victim::None);
  EXPECT_EQ(ref.replay, 0) << ref.replay_log;
  EXPECT_EQ(ref.estimator, 0) << ref.estimator_log;
  EXPECT_EQ(ref.recommender, 0) << ref.recommender_log;
  EXPECT_EQ(ref.recorder, 0) << ref.recorder_log;
  const RunOutcome run = run_pipeline(work / "crashed", ft::domain_id(7 + 2 * static_cast<int>(victim)), victim);
  EXPECT_EQ(run.killed, 128 + 9);
  EXPECT_EQ(run.replay, 0) << run.replay_log;
  EXPECT_EQ(run.estimator, 0) << run.estimator_log;
  EXPECT_EQ(run.recommender, 0) << run.recommender_log;
  EXPECT_EQ(run.recorder, 0) << run.recorder_log;

  // Nothing lost, nothing twice, no reset: in both runs (the reference proves the check can pass).
  for (const RunOutcome* r : {&ref, &run}) {
    expect_every_index_once(r->recording / ("conditions_" + kGroup + "_meanabs.csv"));
    const auto factor_files = ft::condition_factor_files(r->recording, kGroup);
    EXPECT_EQ(factor_files.size(), 2u) << "condition-level filter and fixed-lag tables";
    for (const auto& [name, path] : factor_files) expect_every_index_once(path);
  }

  // Every snapshot reached the alarm engine exactly once: its observation count (kept in the checkpoint, so
  // the restarted recommender reports the total) is the replay's 984; a snapshot missed while no recommender
  // ran would leave it short.
  const std::string observations = R"(asset 'ims2-shaft1' condition level: (\d+) observations, )";
  EXPECT_EQ(ft::grab(ref.recommender_log, observations), std::to_string(kSnapshots)) << ref.recommender_log;
  EXPECT_EQ(ft::grab(run.recommender_log, observations), std::to_string(kSnapshots)) << run.recommender_log;

  // The alarms equal the uncrashed run's; no id raised twice.
  const auto expected = ft::alarm_histories(ft::read_csv(ref.recording / "alarms.csv"), kGroup);
  const auto got = ft::alarm_histories(ft::read_csv(run.recording / "alarms.csv"), kGroup);
  EXPECT_FALSE(expected.empty()) << "IMS test 2 raises alarms from snapshot 533";
  EXPECT_TRUE(got == expected) << "uncrashed run:\n" << ft::describe(expected) << "with kill -9 of " << label << ":\n"
                               << ft::describe(got);
  for (const auto& [id, h] : got) {
    EXPECT_EQ(std::count_if(h.events.begin(), h.events.end(), [](const std::string& e) { return e.rfind("raised/", 0) == 0; }),
              1)
        << "alarm id raised more than once (reused): " << id;
  }
  // The prognoses equal the uncrashed run's byte for byte: the trends are in the recommender's
  // checkpoint, and the last snapshot's prognoses are re-published at a restart (the recorder drops repeats).
  const auto bytes = [](const ft::fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string prognosis_ref = bytes(ref.recording / "prognosis.csv");
  EXPECT_GT(std::count(prognosis_ref.begin(), prognosis_ref.end(), '\n'), 100) << "IMS test 2 has prognoses from 533";
  EXPECT_TRUE(bytes(run.recording / "prognosis.csv") == prognosis_ref)
      << "prognosis.csv differs after the kill -9 of " << label;
  if (victim == Victim::Recommender) {
    const auto first = ft::raised_ids(run.victim_first_log);
    const auto second = ft::raised_ids(run.recommender_log);
    EXPECT_FALSE(first.empty());
    for (const auto& id : second) {
      EXPECT_EQ(std::count(first.begin(), first.end(), id), 0) << "alarm id reused after the restart: " << id;
    }
    EXPECT_NE(run.recommender_log.find("resumed from checkpoint: "), std::string::npos) << run.recommender_log;
    std::printf("[ fault    ] recommender raised before the kill: %zu ids, after the restart: %zu ids; restarted: "
                "resumed from checkpoint: %s observations, %s re-sent observations dropped\n",
                first.size(), second.size(), ft::grab(run.recommender_log, R"(resumed from checkpoint: (\d+) observations)").c_str(),
                ft::grab(run.recommender_log, R"((\d+) re-sent observations dropped)").c_str());
  }

  const auto sent = [](const std::string& log) { return ft::grab(log, R"(summary topic=causal_twin/condition_input sent=(\d+))"); };
  std::printf("[ fault    ] %s: replay sent %s (killed process, last progress line: %s), estimator %s, skipped %s\n", label.c_str(),
              sent(run.replay_log).c_str(),
              victim == Victim::Replay ? ft::grab_last(run.victim_first_log, R"(progress: (\d+/\d+) snapshots)").c_str() : "-",
              ft::grab(run.estimator_log, R"((causal-estimator: received [^\n]*))").c_str(),
              ft::grab(run.estimator_log, R"((\d+) inputs processed before a restart skipped)").c_str());
  std::printf("[ fault    ] recommender: %s observations in all (uncrashed: %s)\n",
              ft::grab(run.recommender_log, observations).c_str(), ft::grab(ref.recommender_log, observations).c_str());
  std::printf("[ fault    ] recorder: %s\n", ft::grab(run.recorder_log, R"((condition vectors [^\n]*))").c_str());
  std::printf("[ fault    ] recorder: %s\n", ft::grab(run.recorder_log, R"((causal factors factors_\S+_condition_filter[^\n]*))").c_str());
  std::printf("[ fault    ] recorder: %s\n", ft::grab(run.recorder_log, R"((alarms: [^\n]*))").c_str());
  std::printf("[ fault    ] alarm ids uncrashed (%zu): %s\n", expected.size(), ids_of(expected).c_str());
  std::printf("[ fault    ] alarm ids with kill (%zu): %s\n", got.size(), ids_of(got).c_str());
  std::printf("[ fault    ] exit codes: killed %d; replay %d, estimator %d, recommender %d, recorder %d\n", run.killed,
              run.replay, run.estimator, run.recommender, run.recorder);

  if (!::testing::Test::HasFailure()) ft::fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

}  // namespace

TEST(CrashRestart, KillNineOfSensorReplayLosesNothing) { crash_and_compare(Victim::Replay, "sensor-replay"); }

TEST(CrashRestart, KillNineOfCausalEstimatorLosesNothing) { crash_and_compare(Victim::Estimator, "causal-estimator"); }

TEST(CrashRestart, KillNineOfAlarmRecommenderLosesNothing) {
  crash_and_compare(Victim::Recommender, "alarm-recommender");
}
