// One factor message per input (estimator.yaml output.factor_messages: set) against one per batch (batch): the
// 6 raw IMS snapshots of deploy/data/ims2-slice through sensor-replay, causal-estimator, alarm-recommender and
// causal-recorder (--sample-level: both time scales recorded), once per mode, on a private domain over the
// loopback-only profile. The recordings must be the same files, byte for byte (the readers hand a set's batches to
// the per-batch handling in order), and every message is counted exactly: what the estimator wrote in sets is
// what the recorder and the recommender received, and the batches inside them are the batches of the batch run.
#include "process_expect.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using causal::test::counts_in_last_line;
using causal::test::ServiceProcess;
using namespace std::chrono_literals;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The per-group summary line's numbers: "{} sample-level and {} condition-level factor messages out".
std::pair<std::uint64_t, std::uint64_t> batches_out(const std::string& log) {
  std::smatch m;
  if (!std::regex_search(log, m, std::regex(R"((\d+) sample-level and (\d+) condition-level factor messages out)"))) {
    return {~0ULL, ~0ULL};
  }
  return {std::stoull(m[1].str()), std::stoull(m[2].str())};
}

struct ModeRun {
  fs::path recording;
  std::string estimator, recorder, recommender;
};

// One run of the four services with `mode` in a copy of the shipped estimator.yaml.
ModeRun run_mode(const fs::path& work, const std::string& mode, int salt) {
  const fs::path dir = work / mode;
  fs::create_directories(dir);
  const fs::path params = dir / "estimator.yaml";
  std::string yaml = read_file(fs::path(CAUSAL_TWIN_DEPLOY_DIR) / "config" / "estimator.yaml");
  const std::string shipped = "factor_messages: batch";
  const auto at = yaml.find(shipped);
  EXPECT_NE(at, std::string::npos) << "the shipped estimator.yaml has no '" << shipped << "'";
  if (at != std::string::npos) yaml.replace(at, shipped.size(), "factor_messages: " + mode);
  std::ofstream(params) << yaml;

  const std::string d = std::to_string(causal::test::private_domain_id(salt));
  const std::string transport = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml";
  const std::vector<std::string> common{"--domain", d, "--transport", transport};
  auto argv = [&](const char* bin, std::vector<std::string> args) {
    std::vector<std::string> v{bin};
    v.insert(v.end(), common.begin(), common.end());
    v.insert(v.end(), args.begin(), args.end());
    return v;
  };
  ModeRun out;
  out.recording = dir / "rec";
  ServiceProcess recorder("causal-recorder",
                          argv(CAUSAL_RECORDER_BIN, {"--out", out.recording.string(), "--sample-level", "--idle-exit", "4",
                                                              "--max-runtime", "120"}),
                          (dir / "recorder.log").string());
  ServiceProcess alarm("alarm-recommender", argv(ALARM_RECOMMENDER_BIN, {"--idle-exit", "4", "--max-runtime", "120"}), (dir / "alarm.log").string());
  ServiceProcess estimator("causal-estimator",
                           argv(CAUSAL_ESTIMATOR_BIN, {"--params", params.string(), "--idle-exit", "3", "--max-runtime", "120", "--wait-for",
                                                       "alarm-recommender", "--wait-for", "causal-recorder",
                                                       "--wait-timeout", "60"}),
                           (dir / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        argv(SENSOR_REPLAY_BIN, {"--ims-dir", (fs::path(CAUSAL_TWIN_DEPLOY_DIR) / "data" / "ims2-slice").string(),
                                                 "--wait-for", "causal-estimator", "--wait-timeout", "60"}),
                        (dir / "replay.log").string());
  EXPECT_NO_FATAL_FAILURE(causal::test::expect_exit_zero(replay, 90s));
  EXPECT_NO_FATAL_FAILURE(causal::test::expect_exit_zero(estimator, 60s));
  EXPECT_NO_FATAL_FAILURE(causal::test::expect_exit_zero(recorder, 60s));
  const auto alarm_code = alarm.wait(60s);  // 6 snapshots: still learning, nothing lost (exit 0)
  EXPECT_EQ(alarm_code.value_or(-1), 0) << alarm.output();
  out.estimator = estimator.output();
  out.recorder = recorder.output();
  out.recommender = alarm.output();
  return out;
}

TEST(FactorSets, OneMessagePerInputRecordsTheSameFilesAsOnePerBatchAndCountsExactly) {
  const fs::path work = fs::temp_directory_path() / ("causal_it_factor_sets_" + std::to_string(getpid()));
  fs::remove_all(work);
  const ModeRun batch = run_mode(work, "batch", 41);
  const ModeRun set = run_mode(work, "set", 42);
  ASSERT_FALSE(HasFailure());

  // The same batches left the estimator in both modes (the per-group line counts batches).
  const auto [sample_batches, condition_batches] = batches_out(batch.estimator);
  ASSERT_NE(sample_batches, ~0ULL) << batch.estimator;
  EXPECT_GT(sample_batches, 0u);
  EXPECT_GT(condition_batches, 0u);
  EXPECT_EQ(batches_out(set.estimator), std::make_pair(sample_batches, condition_batches)) << set.estimator;

  // batch: one message per batch, on causal_twin/causal_factors only.
  EXPECT_EQ(counts_in_last_line(batch.estimator, "summary topic=causal_twin/causal_factors/sample")["sent"], sample_batches);
  EXPECT_EQ(counts_in_last_line(batch.estimator, "summary topic=causal_twin/causal_factors/condition")["sent"],
            condition_batches);
  EXPECT_EQ(batch.estimator.find("causal_factor_sets"), std::string::npos);
  EXPECT_EQ(counts_in_last_line(batch.recommender, "summary topic=causal_twin/causal_factors ")["received"],
            sample_batches + condition_batches) << batch.recommender;
  EXPECT_EQ(batch.recorder.find("summary topic=causal_twin/causal_factor_sets"), std::string::npos);

  // set: one message per input and level, fewer than the batches, all received; the batches inside are the same.
  auto sets_sent = counts_in_last_line(set.estimator, "summary topic=causal_twin/causal_factor_sets/sample");
  auto cond_sets_sent = counts_in_last_line(set.estimator, "summary topic=causal_twin/causal_factor_sets/condition");
  const std::uint64_t sets = sets_sent["sent"] + cond_sets_sent["sent"];
  EXPECT_EQ(sets_sent["dropped"] + sets_sent["failed"] + cond_sets_sent["dropped"] + cond_sets_sent["failed"], 0u);
  EXPECT_GT(sets_sent["sent"], 0u) << set.estimator;
  EXPECT_LT(sets_sent["sent"], sample_batches) << set.estimator;
  EXPECT_EQ(set.estimator.find("summary topic=causal_twin/causal_factors/"), std::string::npos) << set.estimator;
  for (const std::string* log : {&set.recorder, &set.recommender}) {
    auto got = counts_in_last_line(*log, "summary topic=causal_twin/causal_factor_sets ");
    EXPECT_EQ(got["received"], sets) << *log;
    EXPECT_EQ(got["batches"], sample_batches + condition_batches) << *log;
    EXPECT_EQ(got["refused"], 0u) << *log;
  }
  EXPECT_EQ(counts_in_last_line(set.recommender, "summary topic=causal_twin/causal_factors ")["received"],
            sample_batches + condition_batches) << set.recommender;

  // The recordings: the same files, byte for byte.
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(batch.recording)) names.push_back(e.path().filename().string());
  std::size_t set_files = 0;
  for (const auto& e : fs::directory_iterator(set.recording)) set_files += e.is_regular_file() ? 1 : 0;
  ASSERT_GE(names.size(), 5u);  // conditions, factors (2 levels x 2 kinds), ...
  EXPECT_EQ(set_files, names.size());
  for (const auto& name : names) {
    EXPECT_EQ(read_file(set.recording / name), read_file(batch.recording / name)) << name << " differs";
  }
  if (!HasFailure()) fs::remove_all(work);
}

}  // namespace
