// A grant holds for the writer's life on alarm-recommender's what-if requests too. An operator identity (its grant
// names no partitions: it may ask about every group) matches the secured alarm-recommender and asks its questions
// (answered); then it adds a group partition to its publisher with Publisher::set_qos, which Fast DDS 2.9 lets
// through with a log line. The recommender refuses every request of that writer from then on, whatever the group:
// counted exactly (summary not_entitled, exit 4), answered "refused", alarmed once per group (HEALTH
// group_not_entitled naming the writer's participant). The attack itself is shared with the estimator's test
// (partition_switch.hpp) and the alarm actions' (recommender_partition_switch.hpp). Private loopback domain;
// about 15 s.
#include "causal/dds/topics.hpp"
#include "causal_twinPubSubTypes.h"
#include "operator_samples.hpp"
#include "recommender_partition_switch.hpp"

#include <gtest/gtest.h>

using namespace causal::test::security;

namespace {

constexpr std::uint64_t kBefore = 6, kAfter = 5;  // requests per group before / after the partition change

TEST(WhatIfGrantLifetime, AnAskerThatChangesItsPartitionsIsRefusedFromThenOn) {
  const RecommenderSwitch attack{"whatif_grant_lifetime", 63, causal::dds::topics::kWhatIfRequest,
                                 causal::dds::profiles::kWhatIfWriter, "whatif-switcher", kBefore, kAfter};
  const auto r =
      switch_against_recommender<causal_twin::WhatIfRequestPubSubType>(attack, whatif_questions("switcher-"));
  ASSERT_NO_FATAL_FAILURE(expect_refused_from_the_change_on(attack, r, "whatif"));
  EXPECT_EQ(occurrences(r.log, "what-if switcher-"), 2 * kBefore) << "the requests before the change answered:\n" << r.log;
}

}  // namespace
