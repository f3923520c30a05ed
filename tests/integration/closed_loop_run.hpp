// The closed prescriptive loop's run over a private loopback domain, shared by the integration test (data, CSV,
// history, /api/state) and the browser test (the Interventions card in Chromium): sensor-sim --plant lever (two
// groups, seed 38, 420 snapshots at 25/s), causal-estimator (learned order), alarm-recommender, causal-recorder
// (CSV and SQLite --db) and twin-web. Both groups get lever advice; only sim-0000's is approved (causal-approve,
// user it-operator, lead 25, duration 24; or the page's approve button, tests/browser). Needs the BINS
// sensor-sim causal-estimator alarm-recommender causal-recorder causal-approve twin-web.
#pragma once

#include "condition_level_params.hpp"
#include "dds_observer.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace causal::test {

inline constexpr int kClosedLoopSnapshots = 420;

// sim-0000's first reliable rank-1 lever recommendation seen on the bus.
inline std::optional<causal_twin::Recommendation> lever_advice(const DdsObserver& observer, const std::string& group) {
  for (const auto& r : observer.recommendations()) {
    if (r.asset_group() == group && r.rank() == 1 && r.action_kind() == "upstream_lever" && r.reliable()) return r;
  }
  return std::nullopt;
}

// The services, started in the constructor (members in start order: the observer first so it hears everything).
struct ClosedLoopRun {
  // web_extra: more twin-web arguments (the browser test's basic authentication and approval lead).
  ClosedLoopRun(const std::filesystem::path& dir, int domain, const std::vector<std::string>& web_extra = {})
      : work(dir),
        d(std::to_string(domain)),
        observer(domain),
        alarm("alarm-recommender",
              {ALARM_RECOMMENDER_BIN, "--domain", d, "--idle-exit", "8", "--max-runtime", "120"},
              (work / "alarm.log").string()),
        recorder("causal-recorder",
                 {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(), "--db", history_uri(),
                  "--idle-exit", "10", "--max-runtime", "120"},
                 (work / "recorder.log").string()),
        web("twin-web", with(web_extra, {TWIN_WEB_BIN, "--domain", d, "--port", "0", "--max-runtime", "150"}),
            (work / "web.log").string()),
        estimator("causal-estimator",
                  {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params",
                   write_condition_level_params(
                       work / "estimator.yaml", "",
                       "{calibration_samples: 200, centre: true, causal_order: lingam, prune_threshold: 0.0}"),
                   "--idle-exit", "3", "--max-runtime", "120", "--wait-for", "alarm-recommender", "--wait-for",
                   "causal-recorder", "--wait-for", "test-observer"},
                  (work / "estimator.log").string()),
        // 25 snapshots/s: the alarm (about snapshot 270) leaves 6 s of data for the approval and its window.
        // It waits for the estimator by name: twin-web reads condition inputs too, and a first matched reader
        // that is twin-web would let the estimator miss snapshot 0.
        sim("sensor-sim",
            {SENSOR_SIM_BIN, "--domain", d, "--plant", "lever", "--groups", "2", "--seed", "38", "--snapshots",
             std::to_string(kClosedLoopSnapshots), "--snapshot-rate", "25", "--wait-timeout", "60", "--wait-for",
             "causal-estimator"},
            (work / "sim.log").string()) {}

  std::string history_uri() const { return "sqlite:" + (work / "history.db").string(); }
  static std::vector<std::string> with(const std::vector<std::string>& extra, std::vector<std::string> argv) {
    argv.insert(argv.end(), extra.begin(), extra.end());
    return argv;
  }

  std::filesystem::path work;
  std::string d;
  DdsObserver observer;
  ServiceProcess alarm, recorder, web, estimator, sim;
  std::optional<causal_twin::Recommendation> advice;  // sim-0000's approved recommendation
};

// Waits (bounded) for sim-0000's lever advice; a fatal failure when none came (ASSERT_NO_FATAL_FAILURE).
inline void wait_for_advice(ClosedLoopRun& run) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!run.advice && std::chrono::steady_clock::now() < until && run.sim.running()) {
    run.advice = lever_advice(run.observer, "sim-0000");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(run.advice.has_value()) << "no lever advice for sim-0000; alarm log:\n" << run.alarm.output();
  EXPECT_EQ(run.advice->intervene_channel(), 2) << run.advice->text();
}

// Waits until every service but twin-web has exited zero, sensor-sim having applied exactly one approval (the
// recorder has then written interventions.csv and intervention_outcomes.csv).
inline void finish_run(ClosedLoopRun& run) {
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(run.sim, std::chrono::seconds(60)));
  const auto sim_counts = counts_in_last_line(run.sim.output(), "sensor-sim: sent");
  EXPECT_EQ(sim_counts.at("applied"), 1u) << run.sim.output();
  EXPECT_EQ(sim_counts.at("refused"), 0u) << run.sim.output();
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(run.estimator, std::chrono::seconds(60)));
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(run.alarm, std::chrono::seconds(60)));
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(run.recorder, std::chrono::seconds(60)));
}

// Waits for sim-0000's lever advice, approves it with causal-approve and finishes the run (finish_run). Fatal
// failures stop the caller (ASSERT_NO_FATAL_FAILURE). causal-approve waits for every reader of the approval,
// twin-web's too, so that the run does not depend on twin-web keeping it for late readers.
inline void approve_and_finish(ClosedLoopRun& run) {
  ASSERT_NO_FATAL_FAILURE(wait_for_advice(run));
  ServiceProcess approve("causal-approve",
                         {CAUSAL_APPROVE_BIN, "--domain", run.d, "--group", "sim-0000", "--recommendation",
                          run.advice->recommendation_id(), "--user", "it-operator", "--lead", "25", "--duration", "24",
                          "--wait-for", "sensor-sim", "--wait-for", "alarm-recommender", "--wait-for",
                          "causal-recorder", "--wait-for", "twin-web", "--timeout", "20"},
                         (run.work / "approve.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(approve, std::chrono::seconds(40)));
  ASSERT_NO_FATAL_FAILURE(finish_run(run));
}

}  // namespace causal::test
