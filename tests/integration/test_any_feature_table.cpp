// Through the real services: any IMS-format feature table, as it is, with
// `sensor-replay --features FILE` alone (no per-file flags), 2-16 channels, time gaps marked as
// discontinuities, and anything refused refused loudly. Variants of IMS test 2 from tests/support/ims_variants.
// Fixed DDS domains of the alarms-suite range: 228 (eight channels), 229 (gaps, then the refusal).
#include "loopback_settings.hpp"
#include "dds_observer.hpp"
#include "feature_table_run.hpp"
#include "ims_variants.hpp"
#include "process_runner.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sys/wait.h>

namespace fs = std::filesystem;
using causal::test::DdsObserver;
using causal::test::ServiceProcess;

namespace {

constexpr std::uint64_t kSeed = 12;

const causal::testing::BaseRun& base() {
  static const auto b = causal::testing::read_base_run(std::string(CAUSAL_TWIN_DEPLOY_DIR) +
                                                       "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  return b;
}

fs::path work_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_it_any_table", name); }

}  // namespace

// Eight channels named "Bearing 1 C1, Bearing 1 C2, ...": accepted out of the box (the structure window stays
// at 100 snapshots, the causal order is learned in two blocks of 4 channels), every vector processed, and the
// failing bearing's sensors are the first alarmed, after the healthy part, with a bearing-1 sensor named as
// root cause.
TEST(AnyFeatureTable, EightChannelsRunOutOfTheBox) {
  const auto v = causal::testing::make_eight_channel_variant(base(), kSeed);
  const fs::path work = work_dir("eight");
  const std::string csv = (work / "eight_channels.csv").string();
  causal::testing::write_variant_csv(v, csv);
  const std::string d = "228";
  DdsObserver observer(228);
  causal::test::FeatureTableRun run(d, csv, work);
  ASSERT_NO_FATAL_FAILURE(run.wait_all());
  run.expect_rows_delivered(984);
  const std::string est = run.estimator.output();
  // The structure window stays at 100 snapshots; the order is learned per block of 4 sensors (logged).
  EXPECT_EQ(est.find("calibration window"), std::string::npos) << est;
  EXPECT_NE(est.find("channels 5-8: "), std::string::npos) << est;
  EXPECT_EQ(observer.factors(causal_twin::CONDITION_LEVEL, causal_twin::FILTER), 984u * 8u);
  EXPECT_EQ(observer.factor_batches(causal_twin::CONDITION_LEVEL, causal_twin::FILTER), 984u);  // one per snapshot

  // First raised degradation alarm after the healthy part, and none in it.
  std::optional<causal_twin::Alarm> first;
  for (const auto& a : observer.alarms()) {
    if (a.state() != causal_twin::RAISED || (a.category() != "degradation" && !a.category().empty())) continue;
    EXPECT_GE(a.sample_index(), v.healthy_end) << "alarm in the healthy part: " << a.alarm_id() << ": " << a.reason();
    if (!first || a.sample_index() < first->sample_index()) first = a;
  }
  ASSERT_TRUE(first.has_value()) << run.alarm.output();
  std::printf("eight channels: first alarm %s at snapshot %llu on %s, root cause %s\n", first->alarm_id().c_str(),
              static_cast<unsigned long long>(first->sample_index()), first->channel_name().c_str(),
              first->root_cause_name().c_str());
  EXPECT_EQ(first->channel_name().rfind("Bearing 1 C", 0), 0u) << first->alarm_id();
  EXPECT_EQ(first->root_cause_name().rfind("Bearing 1 C", 0), 0u) << first->reason();
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

// Time gaps of hours and days in the table: the replay publishes exactly the rows after a gap (interval > 3 x
// the median) as discontinuities, and logs them; the estimator passes the flags on. Then a table the model
// cannot take (one channel) is refused loudly: estimator exit 4, an input_refused data-quality alarm on the
// alarm topic, and launch.sh exits non-zero within its drain bound instead of hanging to --max-runtime.
TEST(AnyFeatureTable, GapsAreDiscontinuitiesAndRefusalIsLoud) {
  const auto v = causal::testing::make_gaps_variant(base(), kSeed);
  std::vector<std::uint64_t> expected = {0};  // the first row starts a segment too
  for (std::size_t i = 1; i < v.time_ns.size(); ++i) {
    if (v.time_ns[i] - v.time_ns[i - 1] != 600LL * 1000000000LL) expected.push_back(i);
  }
  ASSERT_EQ(expected.size(), 4u);
  const fs::path work = work_dir("gaps");
  const std::string csv = (work / "gaps.csv").string();
  causal::testing::write_variant_csv(v, csv);
  const std::string d = "229";
  {
    causal::dds::DdsSettings s = causal::test::loopback_settings(229, "test-conditions");
    causal::dds::Participant participant(s);
    causal::dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> factors(participant, causal::dds::topics::kCausalFactors,
                                                                           causal::dds::profiles::kCausalFactorsReader);
    causal::dds::TypedReader<causal_twin::ConditionVectorPubSubType> conditions(
        participant, causal::dds::topics::kConditionVector, causal::dds::profiles::kConditionVectorReader);
    ServiceProcess estimator("causal-estimator",
                             {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--idle-exit", "4", "--max-runtime", "180", "--wait-for",
                              "test-conditions"},
                             (work / "estimator.log").string());
    ServiceProcess replay("sensor-replay", {SENSOR_REPLAY_BIN, "--domain", d, "--features", csv, "--wait-for",
                                            "causal-estimator", "--wait-timeout", "60"},
                          (work / "replay.log").string());
    std::map<std::uint64_t, bool> flags;  // snapshot -> discontinuity, as the estimator published it
    auto drain = [&] {
      conditions.take_all([&](const causal_twin::ConditionVector& c, const auto&) { flags[c.snapshot_index()] = c.discontinuity(); });
      factors.take_all([](const auto&, const auto&) {});
    };
    std::optional<int> estimator_code;
    for (int i = 0; i < 1800 && !estimator_code; ++i) {  // 180 s
      drain();
      estimator_code = estimator.wait(std::chrono::milliseconds(100));
    }
    drain();
    ASSERT_TRUE(estimator_code.has_value()) << estimator.output();
    EXPECT_EQ(*estimator_code, 0) << estimator.output();
    const auto replay_code = replay.wait(std::chrono::seconds(30));
    ASSERT_TRUE(replay_code.has_value()) << replay.output();
    EXPECT_EQ(*replay_code, 0) << replay.output();
    const std::string rep = replay.output();
    EXPECT_EQ(causal::test::logged_number(rep, R"(summary topic=causal_twin/condition_input sent=\d+ rewinds=\d+ time_gaps=(\d+))"), 3u) << rep;
    for (std::size_t k = 1; k < expected.size(); ++k) {
      EXPECT_NE(rep.find("before snapshot " + std::to_string(expected[k]) + " "), std::string::npos) << rep;
    }
    ASSERT_EQ(flags.size(), 984u);
    std::vector<std::uint64_t> flagged;
    for (const auto& [index, disc] : flags) {
      if (disc) flagged.push_back(index);
    }
    EXPECT_EQ(flagged, expected);
  }

  // One channel: refused loudly.
  const std::string one = (work / "one_channel.csv").string();
  {
    std::ofstream out(one);
    out << ",Bearing 1\n";
    for (std::size_t i = 0; i < 40; ++i) out << "2004-02-12 1" << i / 6 << ":" << (i % 6) << "0:00," << 0.05 + 0.001 * static_cast<double>(i % 7) << "\n";
  }
  DdsObserver observer(229);
  const std::string cmd = "CAUSAL_TWIN_BUILD_DIR='" + std::string(CAUSAL_TWIN_BUILD_DIR) + "' '" +
                          std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/launch.sh' --domain 229 --max-runtime 120 --features '" +
                          one + "' > '" + (work / "launch.out").string() + "' 2>&1";
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ifstream in(work / "launch.out");
  const std::string launch_out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(WIFEXITED(status)) << launch_out;
  EXPECT_EQ(WEXITSTATUS(status), 4) << launch_out;
  EXPECT_LT(took, 60.0) << "launch.sh must not wait for --max-runtime after a refusal";
  EXPECT_NE(launch_out.find("causal-estimator exited with code 4"), std::string::npos) << launch_out;
  bool alarm_seen = false;
  for (int i = 0; i < 50 && !alarm_seen; ++i) {
    for (const auto& a : observer.alarms()) {
      alarm_seen = alarm_seen || (a.kind() == "input_refused" && a.category() == "data_quality" && a.state() == causal_twin::RAISED);
    }
    if (!alarm_seen) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(alarm_seen) << launch_out;
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
