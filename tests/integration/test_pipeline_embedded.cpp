// Walking skeleton end to end: the three real service processes replay the embedded IMS slice over a
// private loopback DDS domain; an observer in this process counts what crosses the wire.
//
// Expectations are derived independently: frame counts from the slice files (read here with causal_io) and
// the frame size the test chooses; factor-message counts from the publication cadence in the parameter
// file this test writes; alarms from what is known about the recording (bearing 1 fails at the end).
#include "dds_observer.hpp"
#include "process_runner.hpp"

#include "causal/io/ims_directory.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;
using causal::test::DdsObserver;
using causal::test::ServiceProcess;

namespace {

constexpr int kFrameSamples = 1024;
constexpr int kPublishEvery = 2048;

using causal::test::slurp;

std::string write_estimator_params(const fs::path& dir) {
  const fs::path p = dir / "estimator.yaml";
  std::ofstream(p) << "sample_level:\n  enabled: true\n  lag_order: 1\n  include_self_lags: false\n  instantaneous_graph: \"\"\n"
                      "  noise: {mode: automatic, q: 1.0e-6, r: 1.0e-2, p0: 1.0, calibration_samples: 4096}\n"
                      "  structure: {calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}\n"
                      "  publish_every: " << kPublishEvery << "\n  fixed_lag: 32\n"
                      "condition_level:\n  enabled: true\n  feature: rms\n  log_transform: true\n"
                      "  window_samples: 0\n  min_samples: 256\n  lag_order: 1\n  include_self_lags: true\n  instantaneous_graph: \"\"\n"
                      "  noise: {mode: fixed, q: 1.0e-4, r: 1.0e-2, p0: 1.0, calibration_samples: 100}\n"
                      "  structure: {calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}\n"
                      "  publish_every: 1\n  fixed_lag: 2\n"
                      "health:\n  deadline_s: 30\n";
  return p.string();
}

// The shipped alarm parameters, with the sample-level baseline set to the healthy half of the slice.
std::string write_alarm_params(const fs::path& dir, int baseline_publications) {
  std::string text = slurp(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/alarms.yaml");
  text = std::regex_replace(text, std::regex("baseline_publications: *[0-9]+"),
                            "baseline_publications: " + std::to_string(baseline_publications));
  const fs::path p = dir / "alarms.yaml";
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace

TEST(PipelineEmbedded, ThreeServicesReplayTheSliceAndRaiseTheBearingOneAlarm) {
  const std::string slice = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-slice";
  const auto listing = causal::io::list_ims_directory(slice);
  ASSERT_EQ(listing.snapshots.size(), 6u) << "the embedded slice should hold 3 healthy and 3 failing snapshots";
  std::size_t expected_frames = 0, total_samples = 0, healthy_samples = 0;
  int channels = 0;
  for (std::size_t i = 0; i < listing.snapshots.size(); ++i) {
    const auto m = causal::io::read_ims_snapshot(listing.snapshots[i].path);
    channels = static_cast<int>(m.cols());
    expected_frames += (static_cast<std::size_t>(m.rows()) + kFrameSamples - 1) / kFrameSamples;
    total_samples += static_cast<std::size_t>(m.rows());
    if (i < 3) healthy_samples += static_cast<std::size_t>(m.rows());
  }
  const std::int64_t first_failing_time = listing.snapshots[3].time_ns;

  const fs::path work = fs::temp_directory_path() / ("causal_it_" + std::to_string(getpid()));
  fs::create_directories(work);
  const int domain = causal::test::private_domain_id(1);
  const std::string d = std::to_string(domain);
  // Baseline: all healthy publications but the last (the engine needs a few to spare).
  const int healthy_publications = static_cast<int>(healthy_samples / kPublishEvery);
  const std::string estimator_params = write_estimator_params(work);
  const std::string alarm_params = write_alarm_params(work, healthy_publications - 1);

  DdsObserver observer(domain);
  ServiceProcess alarm("alarm-recommender",
                       {ALARM_RECOMMENDER_BIN, "--domain", d, "--params", alarm_params, "--idle-exit", "5",
                        "--max-runtime", "240"},
                       (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params", estimator_params, "--idle-exit", "4",
                            "--max-runtime", "240", "--wait-for", "alarm-recommender", "--wait-for", "test-observer"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--ims-dir", slice, "--frame-samples",
                         std::to_string(kFrameSamples), "--wait-for", "causal-estimator", "--wait-for", "test-observer", "--wait-timeout", "60"},
                        (work / "replay.log").string());

  const auto replay_code = replay.wait(std::chrono::seconds(180));
  ASSERT_TRUE(replay_code.has_value()) << "sensor-replay did not finish in 180 s:\n" << replay.output();
  EXPECT_EQ(*replay_code, 0) << replay.output();
  const auto est_code = estimator.wait(std::chrono::seconds(120));
  const auto alarm_code = alarm.wait(std::chrono::seconds(120));
  ASSERT_TRUE(est_code.has_value()) << estimator.output();
  ASSERT_TRUE(alarm_code.has_value()) << alarm.output();
  EXPECT_EQ(*est_code, 0) << estimator.output();
  EXPECT_EQ(*alarm_code, 0) << alarm.output();

  // Frames: every frame the replay published reached the observer.
  EXPECT_EQ(observer.frames(), expected_frames);
  // Factor vectors: one per outcome every kPublishEvery samples, for the filter and its fixed-lag twin.
  const std::size_t sample_msgs = (total_samples / kPublishEvery) * static_cast<std::size_t>(channels);
  EXPECT_EQ(observer.factors(causal_twin::SAMPLE_LEVEL, causal_twin::FILTER), sample_msgs);
  EXPECT_EQ(observer.factors(causal_twin::SAMPLE_LEVEL, causal_twin::FIXED_LAG_SMOOTHER), sample_msgs);
  // ... batched: one message per published index carries every outcome.
  EXPECT_EQ(observer.factor_batches(causal_twin::SAMPLE_LEVEL, causal_twin::FILTER), total_samples / kPublishEvery);
  EXPECT_EQ(observer.factor_batches(causal_twin::SAMPLE_LEVEL, causal_twin::FIXED_LAG_SMOOTHER),
            total_samples / kPublishEvery);
  // Condition level: one per outcome per snapshot.
  const std::size_t condition_msgs = listing.snapshots.size() * static_cast<std::size_t>(channels);
  EXPECT_EQ(observer.factors(causal_twin::CONDITION_LEVEL, causal_twin::FILTER), condition_msgs);
  EXPECT_EQ(observer.factors(causal_twin::CONDITION_LEVEL, causal_twin::FIXED_LAG_SMOOTHER), condition_msgs);
  EXPECT_EQ(observer.factor_batches(causal_twin::CONDITION_LEVEL, causal_twin::FILTER), listing.snapshots.size());
  EXPECT_EQ(observer.factor_batches(causal_twin::CONDITION_LEVEL, causal_twin::FIXED_LAG_SMOOTHER),
            listing.snapshots.size());
  // Factor names follow x{k}{j} / xL{k}{j}: G=4, M=1 gives 24 sample-level names.
  const auto names = observer.factor_names_seen(causal_twin::SAMPLE_LEVEL);
  EXPECT_EQ(names.size(), 24u);
  EXPECT_NE(std::find(names.begin(), names.end(), "x12"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "xL43"), names.end());

  // Alarms: bearing 1 alarmed with root cause bearing 1, nothing raised on healthy data.
  const auto alarms = observer.alarms();
  bool bearing1 = false;
  for (const auto& a : alarms) {
    EXPECT_GE(a.raised_time_ns(), first_failing_time) << "alarm on healthy data: " << a.alarm_id() << ": " << a.reason();
    if (a.channel() == 1 && a.root_cause_channel() == 1 && a.state() != causal_twin::CLEARED) bearing1 = true;
  }
  EXPECT_TRUE(bearing1) << "no alarm on bearing 1 with root cause bearing 1; alarm log:\n" << alarm.output();

  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
