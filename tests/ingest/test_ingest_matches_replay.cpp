// End to end: the embedded IMS slice (deploy/data/ims2-slice) fed to sensor-ingest through stdin as CSV
// blocks, as a DAQ program would stream it, and the same slice replayed by sensor-replay, both into one
// causal-estimator as two asset groups. The frames must be the same field for field (but `source`), and the
// estimator's factors of the two groups identical: the adapter is a drop-in source for the estimator.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "causal/io/ims_directory.hpp"
#include "ingest_test_support.hpp"

namespace fs = std::filesystem;
using causal::test::ServiceProcess;

namespace {

constexpr int kDomain = 82;  // this helper's range, this test's alone: its estimator would take every group
constexpr Eigen::Index kFrameSamples = 1024;
constexpr double kSampleRate = 20000.0;  // sensor-replay's default for IMS data

// Every snapshot as CSV blocks of kFrameSamples rows, times as sensor-replay stamps them, the last block of
// a snapshot with end_of_segment=1. %.17g: every double is written so that it reads back exactly.
std::string slice_as_csv_blocks(const std::string& group) {
  const auto listing = causal::io::list_ims_directory(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-slice");
  std::string out;
  std::uint64_t sequence = 0;
  char number[64];
  for (const auto& snap : listing.snapshots) {
    const Eigen::MatrixXd m = causal::io::read_ims_snapshot(snap.path);
    for (Eigen::Index row = 0; row < m.rows(); row += kFrameSamples) {
      const Eigen::Index rows = std::min(kFrameSamples, m.rows() - row);
      const auto t0 = snap.time_ns + static_cast<std::int64_t>(static_cast<double>(row) * (1e9 / kSampleRate));
      out += "#block asset_group=" + group +
             " channels=bearing1,bearing2,bearing3,bearing4 sample_rate_hz=20000 unit=V t0_ns=" + std::to_string(t0) +
             " sequence=" + std::to_string(sequence++) + " samples=" + std::to_string(rows) +
             (row + rows == m.rows() ? " end_of_segment=1" : "") + "\n";
      for (Eigen::Index r = row; r < row + rows; ++r) {
        for (Eigen::Index c = 0; c < m.cols(); ++c) {
          std::snprintf(number, sizeof number, "%.17g", m(r, c));
          out += (c ? "," : "") + std::string(number);
        }
        out += "\n";
      }
    }
  }
  return out;
}

}  // namespace

TEST(IngestMatchesReplay, ImsSliceThroughStdinGivesTheSameFramesAndFactors) {
  const fs::path work = fs::temp_directory_path() / ("causal_ingest_e2e_" + std::to_string(getpid()));
  fs::create_directories(work);
  const std::string via_ingest = "e2e-ingest", via_replay = "e2e-replay";
  std::ofstream(work / "slice.csv") << slice_as_csv_blocks(via_ingest);
  const std::string d = std::to_string(kDomain);
  const std::string transport = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml";

  causal::test::FrameRecorder recorder(kDomain, "ingest-test-e2e");
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--transport", transport, "--idle-exit", "4",
                            "--max-runtime", "150", "--wait-for", "ingest-test-e2e"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--transport", transport, "--ims-dir",
                         std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-slice", "--asset-group", via_replay,
                         "--frame-samples", std::to_string(kFrameSamples), "--wait-for", "causal-estimator",
                         "--wait-for", "ingest-test-e2e", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  std::string command = std::string("exec '") + SENSOR_INGEST_BIN + "' --domain " + d + " --transport '" + transport +
                        "' --source - --wait-for causal-estimator --wait-for ingest-test-e2e --wait-timeout 60"
                        " --max-runtime 150 < '" +
                        (work / "slice.csv").string() + "'";
  ServiceProcess ingest("sensor-ingest", {"/bin/sh", "-c", command}, (work / "ingest.log").string());

  const auto ingest_code = ingest.wait(std::chrono::seconds(150));
  const auto replay_code = replay.wait(std::chrono::seconds(150));
  ASSERT_TRUE(ingest_code && replay_code) << ingest.output() << replay.output();
  EXPECT_EQ(*ingest_code, 0) << ingest.output();  // nothing rejected, nothing lost
  EXPECT_EQ(*replay_code, 0) << replay.output();
  const auto estimator_code = estimator.wait(std::chrono::seconds(120));
  ASSERT_TRUE(estimator_code) << estimator.output();
  EXPECT_EQ(*estimator_code, 0) << estimator.output();

  const auto a = recorder.frames(via_ingest), b = recorder.frames(via_replay);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 0u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(a[k].sequence, b[k].sequence);
    EXPECT_EQ(a[k].first_sample_index, b[k].first_sample_index);
    EXPECT_EQ(a[k].snapshot_index, b[k].snapshot_index);
    EXPECT_EQ(a[k].time_ns, b[k].time_ns);
    EXPECT_EQ(a[k].sample_rate_hz, b[k].sample_rate_hz);
    EXPECT_EQ(a[k].unit, b[k].unit);
    EXPECT_EQ(a[k].channel_names, b[k].channel_names);
    EXPECT_EQ(a[k].discontinuity, b[k].discontinuity);
    EXPECT_EQ(a[k].end_of_segment, b[k].end_of_segment);
    EXPECT_EQ(a[k].samples_per_channel, b[k].samples_per_channel);
    EXPECT_TRUE(a[k].samples == b[k].samples);
  }
  const auto fa = recorder.factors(via_ingest), fb = recorder.factors(via_replay);
  ASSERT_GT(fa.size(), 0u);
  ASSERT_EQ(fa.size(), fb.size());
  std::size_t condition_level = 0;
  for (const auto& [key, f] : fa) {
    const auto it = fb.find(key);
    ASSERT_NE(it, fb.end());
    EXPECT_EQ(f.factors, it->second.factors);
    EXPECT_EQ(f.factor_std, it->second.factor_std);
    EXPECT_EQ(f.time_ns, it->second.time_ns);
    if (std::get<0>(key) == causal_twin::CONDITION_LEVEL) ++condition_level;
  }
  std::cout << a.size() << " frames and " << fa.size() << " factor messages (" << condition_level
            << " condition level) per group, identical\n";
  if (!HasFailure()) fs::remove_all(work);
}
