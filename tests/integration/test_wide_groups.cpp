// Wide asset groups through the real services: IMS test 2 with every bearing copied 5 times (20 channels,
// tests/support ims_variants make_replicated_variant: copy c = base x (1 + 0.1 c) x (1 + 3 % noise)) replayed
// by sensor-replay --features, run by causal-estimator and judged by alarm-recommender with the shipped
// parameters. The verdict must be the 4-channel one: nothing before snapshot 500, the first degradation alarm
// on a bearing-1 sensor at or before 560 with a bearing-1 sensor as root cause, critical on a bearing-1 sensor
// at the end, and every vector and factor set delivered (exact counts). Why it failed before: the structure
// window grew to 10 x 20 x 2 = 400 snapshots and the recommender kept only the last 256 condition vectors
// while it waited for their factors, so the engine's baseline observations had no features.
// A private domain id per run (process_runner.hpp: claimed, never shared with a concurrent test).
#include "dds_observer.hpp"
#include "feature_table_run.hpp"
#include "ims_variants.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <regex>

namespace fs = std::filesystem;
using causal::test::DdsObserver;
using causal::test::ServiceProcess;

namespace {

bool bearing1(const std::string& name) { return name.rfind("Bearing 1 C", 0) == 0; }

}  // namespace

TEST(WideGroups, TwentyChannelsGiveTheFourChannelVerdict) {
  const auto base = causal::testing::read_base_run(std::string(CAUSAL_TWIN_DEPLOY_DIR) +
                                                   "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  const auto v = causal::testing::make_replicated_variant(base, 5, 32);
  ASSERT_EQ(v.values.cols(), 20);
  const fs::path work = fs::temp_directory_path() / ("causal_it_wide_" + std::to_string(getpid()));
  fs::create_directories(work);
  const std::string csv = (work / "replicated_5.csv").string();
  causal::testing::write_variant_csv(v, csv);
  // The shipped alarm parameters with the recommendations off: the advice's Monte Carlo over a 20-channel model
  // costs 3-6 s per alarm on a loaded 2-core machine (about 30 alarms here), which this test of the verdict
  // does not need to wait for (docs/results-ims.md, "Wide asset groups").
  std::ifstream shipped(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/alarms.yaml");
  const std::string yaml((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
  const std::regex advice_on(R"((\nrecommendations:[^\n]*\n  enabled: )true)");
  ASSERT_TRUE(std::regex_search(yaml, advice_on));
  const std::string params = (work / "alarms.yaml").string();
  std::ofstream(params) << std::regex_replace(yaml, advice_on, "$1false");
  const int domain = causal::test::private_domain_id(27);
  const std::string d = std::to_string(domain);
  DdsObserver observer(domain);
  causal::test::FeatureTableRun run(d, csv, work, {"--params", params});
  ASSERT_NO_FATAL_FAILURE(run.wait_all());
  EXPECT_EQ(*run.alarm_code, 0) << run.alarm.output();

  // Every vector recorded, exactly.
  run.expect_rows_delivered(984);
  const std::string est = run.estimator.output(), rec = run.alarm.output();
  EXPECT_EQ(causal::test::logged_number(rec, R"(summary topic=causal_twin/condition_vector received=(\d+))"), 984u) << rec;
  EXPECT_EQ(causal::test::logged_number(rec, R"(condition level: (\d+) observations)"), 984u) << rec;
  EXPECT_EQ(observer.factors(causal_twin::CONDITION_LEVEL, causal_twin::FILTER), 984u * 20u);
  EXPECT_EQ(observer.factor_batches(causal_twin::CONDITION_LEVEL, causal_twin::FILTER), 984u);
  // The structure window stays at the configured 100 snapshots, learned per block of 5 sensors.
  EXPECT_EQ(est.find("calibration window"), std::string::npos) << est;
  EXPECT_NE(est.find("channels 16-20: "), std::string::npos) << est;

  // Nothing before 500; the first degradation alarm on bearing 1 by 560, root cause bearing 1; critical at the end.
  std::optional<causal_twin::Alarm> first;
  std::map<std::string, causal_twin::Alarm> last;  // by alarm id
  for (const auto& a : observer.alarms()) {
    if (a.category() != "degradation") continue;
    EXPECT_GE(a.sample_index(), 500u) << "alarm in the healthy part: " << a.alarm_id() << ": " << a.reason();
    last[a.alarm_id()] = a;
    if (a.state() == causal_twin::RAISED && (!first || a.sample_index() < first->sample_index())) first = a;
  }
  ASSERT_TRUE(first.has_value()) << rec;
  std::printf("twenty channels: first alarm %s at snapshot %llu on %s, root cause %s\n", first->alarm_id().c_str(),
              static_cast<unsigned long long>(first->sample_index()), first->channel_name().c_str(),
              first->root_cause_name().c_str());
  EXPECT_LE(first->sample_index(), 560u);
  EXPECT_TRUE(bearing1(first->channel_name())) << first->alarm_id();
  EXPECT_TRUE(bearing1(first->root_cause_name())) << first->reason();
  bool critical_on_bearing1 = false;
  for (const auto& [id, a] : last) {
    if (a.state() == causal_twin::CLEARED) continue;
    std::printf("open at the end: %s %s severity %d root cause %s\n", id.c_str(), a.channel_name().c_str(),
                static_cast<int>(a.severity()), a.root_cause_name().c_str());
    critical_on_bearing1 = critical_on_bearing1 || (a.severity() == causal_twin::CRITICAL && bearing1(a.channel_name()));
  }
  EXPECT_TRUE(critical_on_bearing1) << rec;
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
