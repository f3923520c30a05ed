// A grant holds for the writer's life on alarm-recommender's alarm actions (acknowledge / shelve), as on its
// what-if requests. An operator identity (its grant names no partitions) matches the secured alarm-recommender and
// sends actions (taken and judged: the alarm ids are unknown, so refused as unknown_alarm); then it adds a group
// partition to its publisher with Publisher::set_qos. The recommender refuses every action of that writer from then
// on, whatever the group, before looking at the alarm: counted exactly (summary not_entitled, exit 4), answered
// "refused", alarmed once per group (HEALTH group_not_entitled naming the writer's participant). The attack is
// recommender_partition_switch.hpp's. Private loopback domain; about 15 s.
#include "../fault/delivery_checks.hpp"
#include "causal/dds/topics.hpp"
#include "causal_twinPubSubTypes.h"
#include "operator_samples.hpp"
#include "recommender_partition_switch.hpp"

#include <gtest/gtest.h>

using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

constexpr std::uint64_t kBefore = 4, kAfter = 3;  // actions per group before / after the partition change

TEST(AlarmActionGrantLifetime, ASenderThatChangesItsPartitionsIsRefusedFromThenOn) {
  const RecommenderSwitch attack{"alarm_action_grant_lifetime", 64, causal::dds::topics::kAlarmAction,
                                 causal::dds::profiles::kAlarmActionWriter, "action-switcher", kBefore, kAfter};
  const auto r =
      switch_against_recommender<causal_twin::AlarmActionPubSubType>(attack, acknowledgements("switcher-", "mallory"));
  ASSERT_NO_FATAL_FAILURE(expect_refused_from_the_change_on(attack, r, "alarm_action"));
  EXPECT_EQ(summary_count(r.log, "causal_twin/alarm_action", "applied"), 0u) << r.log;
  EXPECT_EQ(summary_count(r.log, "causal_twin/alarm_action_result", "sent"), 2 * (kBefore + kAfter)) << r.log;
  EXPECT_EQ(occurrences(r.log, ": unknown alarm id '"), 2 * kBefore) << "judged on the alarm before the change:\n"
                                                                     << r.log;
  EXPECT_EQ(occurrences(r.log, ": refused: the sender may not act on asset group"), 2 * kAfter) << r.log;
}

}  // namespace
