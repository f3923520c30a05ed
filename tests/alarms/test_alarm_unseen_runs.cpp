// Two runs the alarm rules were not tuned on (tests/support/ims_variants_unseen.hpp), through the services'
// chain (causal-estimator's condition pipeline -> observation rule -> AlarmEngine, shipped parameters):
//  * relevelled_failure: after a 6-day gap every level stands 20-45 % higher; bearing 1 C1 holds at x1.5-1.6
//    its post-gap level for 10 h, then after a short gap rises to x2.5-3.3 in the last 4 snapshots. The plateau
//    is alarmed, the alarm escalates within 2 snapshots of the final crossing of 2x (the median of 5 needs 3
//    values above), the run ends at warning or critical on bearing 1, nothing is alarmed while healthy.
//  * low_baseline_stretch: IMS test 2 with Bearing 4's baseline learned 8 % below its warm-up level, then back
//    inside that earlier range and one +20 % excursion for 4 snapshots: no degradation alarm before 500;
//    bearing 1 still alarmed first, by 547, root cause bearing 1.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "causal/alarms/alarm_pipeline.hpp"
#include "ims_variants_unseen.hpp"
#include "variant_series.hpp"

namespace causal::alarms {
namespace {

using causal::testing::Variant;

const causal::testing::BaseRun& base() {
  static const auto b = causal::testing::read_base_run(std::string(CAUSAL_TWIN_DEPLOY_DIR) +
                                                       "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  return b;
}

using causal::alarms::test::failing;
using causal::alarms::test::series_of;

void print_events(const Variant& v, const std::vector<AlarmEvent>& events) {
  for (const auto& e : events)
    std::printf("%s %llu %s %s %s %s: %.240s\n", v.name.c_str(), static_cast<unsigned long long>(e.index),
                to_string(e.state), to_string(e.severity), v.channel_names[static_cast<std::size_t>(e.channel)].c_str(),
                e.kind.c_str(), e.reason.c_str());
}

}  // namespace

TEST(AlarmUnseenRuns, RelevelledFailureEscalatesOnTheFailingBearing) {
  const Variant v = causal::testing::make_relevelled_failure_variant(base(), 32);
  const causal::testing::RelevelledFailureRows at;
  const auto res = causal::alarms::run_condition_pipeline(series_of(v), causal::alarms::shipped_options(v.name));
  print_events(v, res.events);
  bool plateau_alarmed = false;
  Severity end = Severity::Advisory;
  std::uint64_t first_warning = ~std::uint64_t{0};
  for (const auto& e : res.events) {
    if (e.category != category::kDegradation) continue;
    if (e.state == AlarmState::Raised) {
      EXPECT_GE(e.index, v.healthy_end) << "healthy part: " << e.reason;
    }
    if (!failing(v, e.channel) || e.state == AlarmState::Cleared) continue;
    if (e.channel == v.failing_channels[0] && e.index >= at.rise && e.index < at.plateau_end) plateau_alarmed = true;
    if (static_cast<int>(e.severity) > static_cast<int>(end)) end = e.severity;
    if (e.severity != Severity::Advisory && e.index < first_warning) first_warning = e.index;
  }
  EXPECT_TRUE(plateau_alarmed) << "bearing 1 C1 held x1.5-1.6 for 10 h without an alarm of its own";
  EXPECT_NE(end, Severity::Advisory) << "the failing bearing ended at advisory";
  // The final values cross 2x at the first row after the short gap; the median of 5 reaches it 2 rows later.
  EXPECT_LE(first_warning, at.plateau_end + 2) << "escalation later than 2 snapshots after the crossing";
  EXPECT_GE(first_warning, at.plateau_end) << "escalated before the level doubled";
  std::printf("relevelled_failure: plateau alarmed %s, end severity %s, first warning at %llu (crossing %zu)\n",
              plateau_alarmed ? "yes" : "no", to_string(end), static_cast<unsigned long long>(first_warning), at.plateau_end);
}

TEST(AlarmUnseenRuns, LowBaselineStretchStaysQuiet) {
  const Variant v = causal::testing::make_low_baseline_stretch_variant(base());
  const auto res = causal::alarms::run_condition_pipeline(series_of(v), causal::alarms::shipped_options(v.name));
  print_events(v, res.events);
  std::uint64_t first = ~std::uint64_t{0};
  int first_channel = -1, root = -1;
  for (const auto& e : res.events) {
    if (e.category != category::kDegradation || e.state != AlarmState::Raised) continue;
    EXPECT_GE(e.index, v.healthy_end) << "healthy part: " << e.reason;
    if (e.index < first) {
      first = e.index;
      first_channel = e.channel;
      root = e.root_cause_channel;
    }
  }
  EXPECT_EQ(first_channel, v.failing_channels[0]);
  EXPECT_EQ(root, v.failing_channels[0]);
  EXPECT_LE(first, 547u);
  std::printf("low_baseline_stretch: first degradation alarm at %llu on channel %d, root cause %d\n",
              static_cast<unsigned long long>(first), first_channel, root);
}

}  // namespace causal::alarms
