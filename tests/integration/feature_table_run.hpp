// One feature table through the three services, for the integration tests of whole runs: alarm-recommender,
// causal-estimator (started once alarm-recommender and the test's observer are discovered) and
// `sensor-replay --features TABLE` alone, on one domain, each logging into the test's work folder.
#pragma once

#include "process_expect.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace causal::test {

// The number in the first match of `pattern`'s group 1 in a log (~0 when there is none, so a check fails).
inline std::uint64_t logged_number(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) return ~0ULL;
  return std::stoull(m[1].str());
}

struct FeatureTableRun {
  // `alarm_options` go to alarm-recommender after --domain (e.g. {"--params", FILE}).
  FeatureTableRun(const std::string& domain, const std::string& table, const std::filesystem::path& work,
                  const std::vector<std::string>& alarm_options = {})
      : alarm("alarm-recommender", alarm_argv(domain, alarm_options), (work / "alarm.log").string()),
        estimator("causal-estimator",
                  {CAUSAL_ESTIMATOR_BIN, "--domain", domain, "--idle-exit", "4", "--max-runtime", "180", "--wait-for",
                   "alarm-recommender", "--wait-for", "test-observer"},
                  (work / "estimator.log").string()),
        replay("sensor-replay",
               {SENSOR_REPLAY_BIN, "--domain", domain, "--features", table, "--wait-for", "causal-estimator",
                "--wait-timeout", "60"},
               (work / "replay.log").string()) {}

  // The replay and then the estimator end with 0 (150 s, 120 s), and alarm-recommender ends (120 s; its code in
  // alarm_code). Call it as ASSERT_NO_FATAL_FAILURE(run.wait_all()).
  void wait_all() {
    ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(150)));
    ASSERT_NO_FATAL_FAILURE(expect_exit_zero(estimator, std::chrono::seconds(120)));
    alarm_code = alarm.wait(std::chrono::seconds(120));
    ASSERT_TRUE(alarm_code.has_value()) << alarm.output();
  }

  // Every one of the table's `rows` sent by the replay and taken by the estimator, none refused (exact counts).
  void expect_rows_delivered(std::uint64_t rows) {
    const std::string est = estimator.output();
    EXPECT_EQ(logged_number(replay.output(), R"(summary topic=causal_twin/condition_input sent=(\d+))"), rows);
    EXPECT_EQ(logged_number(est, R"(summary topic=causal_twin/condition_input received=(\d+))"), rows) << est;
    EXPECT_EQ(logged_number(est, R"(summary topic=causal_twin/condition_input received=\d+ refused=(\d+))"), 0u) << est;
  }

  ServiceProcess alarm, estimator, replay;
  std::optional<int> alarm_code;

 private:
  static std::vector<std::string> alarm_argv(const std::string& domain, const std::vector<std::string>& options) {
    std::vector<std::string> argv{ALARM_RECOMMENDER_BIN, "--domain", domain};
    argv.insert(argv.end(), options.begin(), options.end());
    for (const char* arg : {"--idle-exit", "5", "--max-runtime", "180"}) argv.emplace_back(arg);
    return argv;
  }
};

}  // namespace causal::test
