// The sensor-replay command line the integration tests share: an IMS-format feature table's _meanabs columns
// as the channels bearing1..bearing4, started once causal-estimator is discovered (it waits up to 60 s); and a
// whole replay through a running estimator.
#pragma once

#include "process_expect.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace causal::test {

// `extra` (e.g. {"--speed", "600"}) goes before the --wait-for options.
inline std::vector<std::string> ims_feature_replay_argv(const std::string& replay_bin, const std::string& domain,
                                                        const std::string& table, std::vector<std::string> extra = {}) {
  std::vector<std::string> argv{replay_bin, "--domain", domain, "--features", table, "--feature-suffix", "_meanabs",
                                "--feature-name", "meanabs", "--channel-names", "bearing1", "bearing2", "bearing3",
                                "bearing4"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  for (const char* arg : {"--wait-for", "causal-estimator", "--wait-timeout", "60"}) argv.emplace_back(arg);
  return argv;
}

// Replays the whole table (exit 0 within 240 s, log in `log`), then waits up to 120 s for `estimator` to drain its
// output and leave (its --idle-exit). Call it as ASSERT_NO_FATAL_FAILURE(replay_through(...)).
inline void replay_through(ServiceProcess& estimator, const std::string& replay_bin, const std::string& domain,
                           const std::string& table, const std::filesystem::path& log) {
  ServiceProcess replay("sensor-replay", ims_feature_replay_argv(replay_bin, domain, table), log.string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(240)));
  ASSERT_TRUE(estimator.wait(std::chrono::seconds(120)).has_value()) << estimator.output();
}

}  // namespace causal::test
