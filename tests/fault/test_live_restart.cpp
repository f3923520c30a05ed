// The live path across restarts and strange input, with real processes: sensor-ingest
// fed through stdin, causal-estimator with checkpoints, on a private loopback domain.
//  * A restarted sensor-ingest with --state-dir continues each group's numbering: the estimator processes every
//    frame of both runs (before: the second run numbered from 0 again and its frames were skipped as processed).
//  * Without it, a restarted estimator refuses the renumbered frames loudly (counted, alarmed, exit 4) instead of
//    skipping them silently, and a SIGTERM never crashes it (before: vector::_M_range_check, exit 1).
//  * A source that names ever new asset groups is stopped by the per-writer quota; absurd rates are rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "process_runner.hpp"
#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::test::counts_in_last_line;
using causal::test::ServiceProcess;

namespace {

constexpr std::size_t kRows = 256;          // samples per block
constexpr std::size_t kBlocksPerSnapshot = 4;
constexpr std::int64_t kPeriodNs = 1000000;  // 1 kHz

fs::path work_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_live_restart", name); }

// `snapshots` snapshots of kBlocksPerSnapshot CSV blocks of a live 2-channel signal (deterministic noise, never
// stuck), source sequence numbers from 0 (a source that restarted counts from 0 again), data times from t0.
std::string csv_stream(const std::string& group, std::size_t snapshots, std::int64_t t0, std::uint64_t seed,
                       double rate_hz = 1000.0) {
  std::string s;
  std::uint64_t x = seed * 2654435761u + 1;
  auto noise = [&x] {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>((x >> 11) % 2000001) / 1e6 - 1.0;
  };
  std::uint64_t sequence = 0;
  for (std::size_t snap = 0; snap < snapshots; ++snap) {
    const std::int64_t start = t0 + static_cast<std::int64_t>(snap) * 600000000000LL;  // 10 min apart
    for (std::size_t b = 0; b < kBlocksPerSnapshot; ++b) {
      char rate[32];
      std::snprintf(rate, sizeof rate, "%.17g", rate_hz);  // std::to_string would write 1e-300 as 0.000000
      s += "#block asset_group=" + group + " channels=c1,c2 sample_rate_hz=" + rate +
           " t0_ns=" + std::to_string(start + static_cast<std::int64_t>(b * kRows) * kPeriodNs) +
           " sequence=" + std::to_string(sequence++) + " samples=" + std::to_string(kRows) +
           (b + 1 == kBlocksPerSnapshot ? " end_of_segment=1" : "") + "\n";
      for (std::size_t i = 0; i < kRows; ++i) {
        const double a = noise();
        s += std::to_string(a) + "," + std::to_string(0.5 * a + noise()) + "\n";
      }
    }
  }
  return s;
}

std::string transport() { return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"; }

std::unique_ptr<ServiceProcess> start_estimator(const fs::path& work, const std::string& domain, const std::string& tag,
                                                std::vector<std::string> extra = {}) {
  std::vector<std::string> args{CAUSAL_ESTIMATOR_BIN, "--domain", domain, "--transport", transport(),
                                "--params", FAULT_ESTIMATOR_PARAMS, "--state-dir", (work / "estimator").string(),
                                "--max-runtime", "60"};
  args.insert(args.end(), extra.begin(), extra.end());
  return std::make_unique<ServiceProcess>("causal-estimator", args, (work / ("estimator-" + tag + ".log")).string());
}

// sensor-ingest reading `input` on stdin until its end; returns its exit code and output.
std::pair<int, std::string> run_ingest(const fs::path& work, const std::string& domain, const std::string& tag,
                                       const std::string& input, bool keep_numbering) {
  const fs::path file = work / ("input-" + tag + ".csv");
  std::ofstream(file) << input;
  std::string command = std::string("exec '") + SENSOR_INGEST_BIN + "' --domain " + domain + " --transport '" +
                        transport() + "' --source - --wait-for causal-estimator --wait-timeout 30 --max-runtime 60";
  if (keep_numbering) command += " --state-dir '" + (work / "ingest").string() + "'";
  command += " < '" + file.string() + "'";
  ServiceProcess ingest("sensor-ingest", {"/bin/sh", "-c", command}, (work / ("ingest-" + tag + ".log")).string());
  const auto code = ingest.wait(std::chrono::seconds(60));
  return {code.value_or(-1), ingest.output()};
}

// SIGTERM once the input has surely been taken (the ingest waited for its acknowledgements before it exited).
int stop(ServiceProcess& p) {
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  return p.terminate(std::chrono::seconds(20));
}

constexpr std::int64_t kT0 = 1700000000000000000LL;
constexpr std::size_t kSnapshots = 3;
constexpr std::uint64_t kFrames = kSnapshots * kBlocksPerSnapshot;

}  // namespace

TEST(LiveRestart, RestartedIngestWithStateDirContinuesItsNumbering) {
  const fs::path work = work_dir("resume");
  const std::string d = std::to_string(causal::test::private_domain_id(61));
  auto estimator = start_estimator(work, d, "1");
  const auto first = run_ingest(work, d, "1", csv_stream("pump-a", kSnapshots, kT0, 1), true);
  ASSERT_EQ(first.first, 0) << first.second;
  // The restarted source counts from 0 again and its data goes on an hour later.
  const auto second = run_ingest(work, d, "2", csv_stream("pump-a", kSnapshots, kT0 + 3600000000000LL, 2), true);
  ASSERT_EQ(second.first, 0) << second.second;
  EXPECT_EQ(counts_in_last_line(second.second, "sensor-ingest: received=")["resumed_groups"], 1u) << second.second;
  const int code = stop(*estimator);
  const std::string out = estimator->output();
  std::cout << out.substr(out.rfind("summary not_processed")).substr(0, 120) << "\n";
  EXPECT_EQ(code, 0) << out;
  EXPECT_EQ(counts_in_last_line(out, "causal-estimator: received frames=")["frames"], 2 * kFrames) << out;
  auto skipped = counts_in_last_line(out, "summary not_processed");
  EXPECT_EQ(skipped["renumbered"], 0u) << out;
  EXPECT_EQ(skipped["already_processed"], 0u) << out;
  if (!HasFailure()) fs::remove_all(work);
}

TEST(LiveRestart, RestartedEstimatorRefusesRenumberedInputLoudlyAndSurvivesSigterm) {
  const fs::path work = work_dir("renumbered");
  const std::string d = std::to_string(causal::test::private_domain_id(62));
  {
    auto estimator = start_estimator(work, d, "1");
    const auto first = run_ingest(work, d, "1", csv_stream("pump-b", kSnapshots, kT0, 3), false);
    ASSERT_EQ(first.first, 0) << first.second;
    EXPECT_EQ(stop(*estimator), 0) << estimator->output();
  }
  // The estimator resumes from its checkpoint; the source restarted without its numbering (0 again, later data).
  auto estimator = start_estimator(work, d, "2");
  const auto second = run_ingest(work, d, "2", csv_stream("pump-b", kSnapshots, kT0 + 3600000000000LL, 4), false);
  ASSERT_EQ(second.first, 0) << second.second;
  const int code = stop(*estimator);
  const std::string out = estimator->output();
  EXPECT_EQ(code, 4) << "refused input must show in the exit code (and never crash, e.g. exit 1):\n" << out;
  auto skipped = counts_in_last_line(out, "summary not_processed");
  std::cout << "not processed: renumbered=" << skipped["renumbered"] << " already_processed="
            << skipped["already_processed"] << "\n";
  EXPECT_EQ(skipped["renumbered"], kFrames) << out;
  EXPECT_EQ(skipped["already_processed"], 0u) << out;
  EXPECT_NE(out.find("numbering went back"), std::string::npos) << out;
  EXPECT_NE(out.find("DATA QUALITY RAISED pump-b/input/input_refused"), std::string::npos) << out;
  if (!HasFailure()) fs::remove_all(work);
}

TEST(LiveRestart, PerWriterQuotaOnAssetGroupsAndAbsurdRatesAreRefusedAndCounted) {
  const fs::path work = work_dir("quota");
  const std::string d = std::to_string(causal::test::private_domain_id(63));
  auto estimator = start_estimator(work, d, "1", {"--max-groups-per-writer", "3"});
  std::string input;
  for (int g = 0; g < 5; ++g) input += csv_stream("flood-" + std::to_string(g), 1, kT0, 10 + g);
  input += csv_stream("slow-rate", 1, kT0, 20, 1e-300);  // rejected by sensor-ingest: 4 blocks
  const auto ingest = run_ingest(work, d, "1", input, false);
  EXPECT_EQ(ingest.first, 4) << ingest.second;  // rejections make the exit code
  const auto in = counts_in_last_line(ingest.second, "sensor-ingest: received=");
  EXPECT_EQ(in.at("published"), 5 * kBlocksPerSnapshot) << ingest.second;
  EXPECT_EQ(in.at("field"), kBlocksPerSnapshot) << ingest.second;
  EXPECT_NE(ingest.second.find("sample_rate_hz 1e-300 is outside"), std::string::npos) << ingest.second;
  const int code = stop(*estimator);
  const std::string out = estimator->output();
  EXPECT_EQ(code, 4) << out;
  auto skipped = counts_in_last_line(out, "summary not_processed");
  EXPECT_EQ(skipped["group_quota"], 2 * kBlocksPerSnapshot) << out;
  EXPECT_EQ(skipped["groups"], 3u) << out;
  EXPECT_NE(out.find("/input/asset_group_quota/"), std::string::npos) << out;
  EXPECT_EQ(std::distance(fs::directory_iterator(work / "estimator"), fs::directory_iterator{}), 3) << out;
  if (!HasFailure()) fs::remove_all(work);
}
