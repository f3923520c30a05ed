// causal::dds::to_alarm (common/dds/src/alarm_conversions.cpp): 0-based engine channels become 1-based IDL
// channels, an unknown root cause becomes 0 with no name, severities / states map one to one.
#include "causal/dds/alarm_conversions.hpp"

#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using causal::alarms::AlarmEvent;
using causal::alarms::AlarmState;
using causal::alarms::Severity;

const std::vector<std::string> kNames{"bearing1", "bearing2", "bearing3", "bearing4"};

AlarmEvent event() {
  AlarmEvent e;
  e.alarm_id = "ims2/3/innovation_rise/7";
  e.channel = 2;
  e.severity = Severity::Warning;
  e.state = AlarmState::Raised;
  e.kind = causal::alarms::kind::kInnovationRise;
  e.raised_time_ns = 1'077'000'000'000'000'000LL;
  e.cleared_time_ns = 0;
  e.index = 533;
  e.root_cause_channel = 0;
  e.factor_names = {"x31", "xL31"};
  e.factor_baseline = {0.1, -0.2};
  e.factor_now = {0.5, 0.3};
  e.score = 17.5;
  e.threshold = 12.25;
  e.reason = "bearing3's own behaviour changed";
  return e;
}

TEST(AlarmConversions, ChannelsBecomeOneBasedWithNames) {
  causal_twin::Alarm a;
  causal::dds::to_alarm("ims2", kNames, event(), a);
  EXPECT_EQ(a.alarm_id(), "ims2/3/innovation_rise/7");
  EXPECT_EQ(a.asset_group(), "ims2");
  EXPECT_EQ(a.channel(), 3u);
  EXPECT_EQ(a.channel_name(), "bearing3");
  EXPECT_EQ(a.root_cause_channel(), 1u);
  EXPECT_EQ(a.root_cause_name(), "bearing1");
  EXPECT_EQ(a.severity(), causal_twin::WARNING);
  EXPECT_EQ(a.state(), causal_twin::RAISED);
  EXPECT_EQ(a.kind(), "innovation_rise");
  EXPECT_EQ(a.raised_time_ns(), 1'077'000'000'000'000'000LL);
  EXPECT_EQ(a.cleared_time_ns(), 0);
  EXPECT_EQ(a.sample_index(), 533u);
  EXPECT_EQ(a.factor_names(), (std::vector<std::string>{"x31", "xL31"}));
  EXPECT_EQ(a.factor_baseline(), (std::vector<double>{0.1, -0.2}));
  EXPECT_EQ(a.factor_now(), (std::vector<double>{0.5, 0.3}));
  EXPECT_EQ(a.score(), 17.5);
  EXPECT_EQ(a.threshold(), 12.25);
  EXPECT_EQ(a.reason(), "bearing3's own behaviour changed");
}

TEST(AlarmConversions, FirstAndLastChannel) {
  causal_twin::Alarm a;
  AlarmEvent e = event();
  e.channel = 0;
  e.root_cause_channel = 3;
  causal::dds::to_alarm("g", kNames, e, a);
  EXPECT_EQ(a.channel(), 1u);
  EXPECT_EQ(a.channel_name(), "bearing1");
  EXPECT_EQ(a.root_cause_channel(), 4u);
  EXPECT_EQ(a.root_cause_name(), "bearing4");
}

TEST(AlarmConversions, UnknownRootCauseIsZeroWithoutName) {
  causal_twin::Alarm a;
  AlarmEvent e = event();
  e.root_cause_channel = -1;
  causal::dds::to_alarm("ims2", kNames, e, a);
  EXPECT_EQ(a.root_cause_channel(), 0u);
  EXPECT_EQ(a.root_cause_name(), "");
  EXPECT_EQ(a.channel(), 3u);
}

TEST(AlarmConversions, ChannelWithoutANameGetsAnEmptyName) {
  causal_twin::Alarm a;
  AlarmEvent e = event();
  e.channel = 7;  // more channels than names given
  causal::dds::to_alarm("ims2", kNames, e, a);
  EXPECT_EQ(a.channel(), 8u);
  EXPECT_EQ(a.channel_name(), "");
  causal::dds::to_alarm("ims2", {}, event(), a);
  EXPECT_EQ(a.channel_name(), "");
  EXPECT_EQ(a.root_cause_name(), "");
}

TEST(AlarmConversions, SeveritiesAndStatesMapOneToOne) {
  const std::pair<Severity, causal_twin::Severity> sev[] = {{Severity::Advisory, causal_twin::ADVISORY},
                                                            {Severity::Warning, causal_twin::WARNING},
                                                            {Severity::Critical, causal_twin::CRITICAL}};
  const std::pair<AlarmState, causal_twin::AlarmState> st[] = {{AlarmState::Raised, causal_twin::RAISED},
                                                               {AlarmState::Escalated, causal_twin::ESCALATED},
                                                               {AlarmState::Cleared, causal_twin::CLEARED}};
  for (const auto& [from, to] : sev) {
    for (const auto& [sfrom, sto] : st) {
      AlarmEvent e = event();
      e.severity = from;
      e.state = sfrom;
      if (sfrom == AlarmState::Cleared) e.cleared_time_ns = e.raised_time_ns + 3'600'000'000'000LL;
      causal_twin::Alarm a;
      causal::dds::to_alarm("ims2", kNames, e, a);
      EXPECT_EQ(a.severity(), to);
      EXPECT_EQ(a.state(), sto);
      EXPECT_EQ(a.cleared_time_ns(), e.cleared_time_ns);
    }
  }
}

TEST(AlarmConversions, AlarmSurvivesCdrSerialisation) {
  causal_twin::Alarm a;
  causal::dds::to_alarm("ims2", kNames, event(), a);
  causal_twin::AlarmPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&a)());
  ASSERT_TRUE(type.serialize(&a, &payload));
  causal_twin::Alarm back;
  ASSERT_TRUE(type.deserialize(&payload, &back));
  // "Unknown" hours are NaN, which never compares equal: check them as NaN, then the rest field by field.
  EXPECT_TRUE(std::isnan(back.hours_to_next_level()));
  EXPECT_TRUE(std::isnan(back.hours_to_next_level_low()));
  EXPECT_TRUE(std::isnan(back.hours_to_next_level_high()));
  for (causal_twin::Alarm* m : {&a, &back}) {
    m->hours_to_next_level(0.0);
    m->hours_to_next_level_low(0.0);
    m->hours_to_next_level_high(0.0);
  }
  EXPECT_TRUE(back == a);
}

TEST(AlarmConversions, DecisionFieldsStartAsNoneAndUnknown) {
  causal_twin::Alarm a;
  causal::dds::to_alarm("ims2", kNames, event(), a);
  EXPECT_EQ(a.action(), "");
  EXPECT_EQ(a.next_level(), "");
  EXPECT_TRUE(std::isnan(a.hours_to_next_level()));
}

}  // namespace
