// Delivery contract on the real raw data: every IMS test-2 snapshot in ../shared/data/ims2/raw replayed as
// fast as possible through sensor-replay -> causal-estimator (shipped parameters) -> causal-recorder
// --sample-level. Every snapshot's condition vector is recorded exactly once (indices 0..N-1) and every
// sample-level factor vector exactly once, per kind (filter, fixed-lag), and no service reports a loss.
//
// Expectations come from the folder, read here: N snapshot files and their line counts (samples per
// channel), and the shipped sample_level.publish_every (deploy/config/estimator.yaml): one factor row per
// 1024 samples, indexed by the source's sample index of the block's last sample (snapshot i's samples are
// numbered from the sum of the earlier snapshots' lengths).
#include "delivery_checks.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace fs = std::filesystem;
using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::uint64_t kPublishEvery = 1024;  // deploy/config/estimator.yaml: sample_level.publish_every
constexpr std::uint64_t kFrameSamples = 1024;  // --frame-samples given to sensor-replay below

// Snapshot files of an IMS directory: named YYYY.MM.DD.hh.mm.ss, optionally .gz (sorted: time order).
std::vector<fs::path> snapshot_files(const fs::path& dir) {
  static const std::regex name_re(R"(\d{4}\.\d{2}\.\d{2}\.\d{2}\.\d{2}\.\d{2}(\.gz)?)");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && std::regex_match(e.path().filename().string(), name_re)) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::uint64_t count_lines(const fs::path& file) {
  const std::string text = read_text(file);
  std::uint64_t n = static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n'));
  if (!text.empty() && text.back() != '\n') ++n;
  return n;
}

}  // namespace

TEST(FullRawReplay, EverySnapshotAndEverySampleLevelFactorVectorRecordedOnce) {
  const fs::path raw = fs::path(CAUSAL_TWIN_SHARED_DIR) / "data" / "ims2" / "raw";
  if (!fs::is_directory(raw)) GTEST_SKIP() << "no raw IMS data at " << raw << " (see ../shared/data/ims2/README.md)";
  const auto files = snapshot_files(raw);
  ASSERT_FALSE(files.empty()) << "no snapshot files in " << raw;
  for (const auto& f : files) {
    ASSERT_NE(f.extension(), ".gz") << "this test counts samples of plain-text snapshots only: " << f;
  }

  // Expected factor rows: one per publish_every samples of each snapshot (the filter restarts at every
  // snapshot, a discontinuity); their indices: the last sample of each block, numbered across the run.
  const std::uint64_t snapshots = files.size();
  std::set<std::uint64_t> expected_sample_indices;
  std::uint64_t first_sample = 0, total_samples = 0;
  for (const auto& f : files) {
    const std::uint64_t lines = count_lines(f);
    ASSERT_EQ(lines % kPublishEvery, 0u) << f << " has " << lines << " samples, not a multiple of " << kPublishEvery;
    ASSERT_EQ(lines % kFrameSamples, 0u) << f << " has " << lines << " samples, not a multiple of " << kFrameSamples;
    for (std::uint64_t end = kPublishEvery; end <= lines; end += kPublishEvery) {
      expected_sample_indices.insert(first_sample + end - 1);
    }
    first_sample += lines;
    total_samples += lines;
  }
  std::printf("[ delivery ] %llu snapshots, %llu samples per channel, %zu expected factor rows per kind\n",
              static_cast<unsigned long long>(snapshots), static_cast<unsigned long long>(total_samples),
              expected_sample_indices.size());

  const fs::path work = work_dir("raw");
  const std::string d = std::to_string(delivery_domain_id(20));
  const auto started = Clock::now();
  ServiceProcess recorder("causal-recorder",
                          {CAUSAL_RECORDER_BIN, "--domain", d, "--out", (work / "rec").string(), "--sample-level",
                           "--idle-exit", "6", "--max-runtime", "280"},
                          (work / "recorder.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "4", "--max-runtime", "280",
                            "--wait-for", "causal-recorder", "--wait-timeout", "60"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--ims-dir", raw.string(), "--speed", "0", "--frame-samples",
                         std::to_string(kFrameSamples), "--wait-for",
                         "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  const auto replay_code = replay.wait(std::chrono::seconds(240));
  ASSERT_TRUE(replay_code.has_value()) << "sensor-replay did not finish in 240 s:\n" << replay.output();
  const double replay_s = std::chrono::duration<double>(Clock::now() - started).count();
  EXPECT_EQ(*replay_code, 0) << replay.output();
  const auto est_code = estimator.wait(std::chrono::seconds(60));
  const auto rec_code = recorder.wait(std::chrono::seconds(60));
  const double total_s = std::chrono::duration<double>(Clock::now() - started).count();
  ASSERT_TRUE(est_code.has_value()) << estimator.output();
  ASSERT_TRUE(rec_code.has_value()) << recorder.output();
  // Snapshots without a condition vector (a window with too few usable samples, e.g. every channel of the last
  // IMS file quarantined: the machine had stopped, the sensors read 0) are stated by the estimator, and its exit
  // code says data was refused.
  const std::uint64_t windows_dropped =
      summary_count(estimator.output(), "causal_twin/condition_vector", "windows_dropped").value_or(~0ULL);
  ASSERT_NE(windows_dropped, ~0ULL) << "the estimator must state the snapshots it could not publish:\n"
                                    << estimator.output();
  EXPECT_EQ(*est_code, windows_dropped > 0 ? 4 : 0) << estimator.output();
  EXPECT_EQ(*rec_code, 0) << recorder.output();
  std::printf("[ delivery ] replay done after %.1f s, every service exited after %.1f s\n", replay_s, total_s);

  // Every service's own counts: all sent, all received, nothing lost, dropped, failed or refused.
  const std::string rep_log = replay.output(), est_log = estimator.output(), rec_log = recorder.output();
  const std::uint64_t frames = total_samples / kFrameSamples;  // every snapshot is a multiple of 1024 (checked)
  EXPECT_EQ(summary_count(rep_log, "causal_twin/vibration_frame", "snapshots"), std::optional<std::uint64_t>(snapshots));
  EXPECT_EQ(summary_count(rep_log, "causal_twin/vibration_frame", "sent"), std::optional<std::uint64_t>(frames));
  EXPECT_EQ(summary_count(est_log, "causal_twin/vibration_frame", "received"), std::optional<std::uint64_t>(frames));
  EXPECT_EQ(summary_count(est_log, "causal_twin/condition_vector", "sent"),
            std::optional<std::uint64_t>(snapshots - windows_dropped))
      << "condition vectors the estimator published: one per snapshot, less the ones it states it could not publish";
  std::printf("[ delivery ] the estimator states %llu snapshot(s) without a condition vector\n",
              static_cast<unsigned long long>(windows_dropped));
  const auto losses = nonzero_losses(rep_log + est_log);
  for (const auto& l : losses) ADD_FAILURE() << "a summary reports a loss: " << l;
  EXPECT_EQ(est_log.find("lost snapshots"), std::string::npos);
  EXPECT_EQ(rec_log.find("lost snapshots"), std::string::npos) << rec_log;
  EXPECT_EQ(rec_log.find("partial rows"), std::string::npos) << rec_log;

  // The recording: conditions once per snapshot 0..N-1, sample-level factors once per 1024-sample block.
  const RecordedFile conditions = read_recorded(work / "rec" / "conditions_ims2-shaft1_meanabs.csv");
  std::set<std::uint64_t> all_snapshots, absent;
  for (std::uint64_t i = 0; i < snapshots; ++i) {
    all_snapshots.insert(i);
    if (conditions.indices.count(i) == 0) absent.insert(i);
  }
  std::printf("[ delivery ] conditions: %llu rows, %zu distinct, missing snapshots: %s\n",
              static_cast<unsigned long long>(conditions.rows), conditions.indices.size(),
              absent.empty() ? "none" : ranges_text(absent).c_str());
  EXPECT_EQ(conditions.rows + windows_dropped, snapshots);
  EXPECT_TRUE(conditions.repeated.empty()) << "condition rows recorded twice, the first " << conditions.repeated.front();
  EXPECT_EQ(absent.size(), windows_dropped) << "snapshots without a condition row: " << ranges_text(absent);
  for (const char* kind : {"filter", "fixed-lag"}) {
    const std::string name = std::string("factors_ims2-shaft1_sample_") + kind + ".csv";
    const RecordedFile f = read_recorded(work / "rec" / name);
    ASSERT_TRUE(f.exists) << name << " not recorded:\n" << rec_log;
    std::printf("[ delivery ] %s: %llu rows, %zu distinct, %llu bytes\n", name.c_str(),
                static_cast<unsigned long long>(f.rows), f.indices.size(), static_cast<unsigned long long>(f.bytes));
    EXPECT_EQ(f.rows, expected_sample_indices.size()) << name;
    EXPECT_TRUE(f.repeated.empty()) << name << ": rows recorded twice, the first " << f.repeated.front();
    EXPECT_TRUE(f.indices == expected_sample_indices) << name << ": the sample indices differ from the 1024-sample blocks";
  }

  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
