// The ISA-18.2 alarm management state machine: acknowledge, shelve / unshelve / expiry (wall clock chosen by the
// test), refusals counted by reason, and the health figures counted exactly in data time.
#include "alarm_management_fixtures.hpp"

#include "causal/alarm_management/alarm_management.hpp"

#include <gtest/gtest.h>

#include <string>

namespace am = causal::alarm_management;
using namespace causal::alarm_management::test;

TEST(AlarmManagement, AcknowledgeHoldsUntilEscalation) {
  am::AlarmManager m;
  EXPECT_FALSE(m.on_event(event("g1/1/cusum/0", am::EventState::Raised, kT0)).acknowledged);
  EXPECT_EQ(m.health("g1", kT0).unacknowledged, 1u);
  const auto o = m.apply(request("r1", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow);
  ASSERT_TRUE(o.applied) << o.error;
  EXPECT_TRUE(o.acknowledged);
  EXPECT_FALSE(o.shelved);
  EXPECT_EQ(m.health("g1", kT0).unacknowledged, 0u);
  EXPECT_TRUE(m.flags("g1/1/cusum/0").acknowledged);
  // Acknowledging again is refused (not applicable), and counted.
  const auto again = m.apply(request("r2", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow);
  EXPECT_FALSE(again.applied);
  EXPECT_EQ(again.refusal, am::Refusal::NotApplicable);
  // An escalation must be acknowledged anew.
  EXPECT_FALSE(m.on_event(event("g1/1/cusum/0", am::EventState::Escalated, kT0)).acknowledged);
  EXPECT_EQ(m.health("g1", kT0 + kS).unacknowledged, 1u);
  EXPECT_EQ(m.counters().applied, 1u);
  EXPECT_EQ(m.counters().refused.at(am::Refusal::NotApplicable), 1u);
}

TEST(AlarmManagement, ClearedAlarmCanBeAcknowledgedAndIsNotOpen) {
  am::AlarmManager m;
  m.on_event(event("g1/2/nis/0", am::EventState::Raised, kT0));
  m.on_event(event("g1/2/nis/0", am::EventState::Cleared, kT0));
  EXPECT_EQ(m.health("g1", kT0 + kS).open, 0u);
  EXPECT_EQ(m.health("g1", kT0 + kS).unacknowledged, 0u);
  EXPECT_TRUE(m.apply(request("r1", "g1/2/nis/0", am::ActionKind::Acknowledge), kNow).applied);
}

TEST(AlarmManagement, RefusalsAreCountedByReason) {
  am::AlarmManager m;
  m.on_event(event("g1/1/cusum/0", am::EventState::Raised, kT0));
  EXPECT_EQ(m.apply(request("r1", "g1/9/cusum/0", am::ActionKind::Acknowledge), kNow).refusal,
            am::Refusal::UnknownAlarm);
  EXPECT_EQ(m.apply(request("r2", "g1/1/cusum/0", am::ActionKind::Acknowledge, 0, "g2"), kNow).refusal,
            am::Refusal::UnknownAlarm);  // the id is another group's
  auto no_user = request("r3", "g1/1/cusum/0", am::ActionKind::Acknowledge);
  no_user.user.clear();
  EXPECT_EQ(m.apply(no_user, kNow).refusal, am::Refusal::BadRequest);
  auto no_reason = request("r4", "g1/1/cusum/0", am::ActionKind::Shelve, kNow + 60 * kS);
  no_reason.reason.clear();
  EXPECT_EQ(m.apply(no_reason, kNow).refusal, am::Refusal::BadRequest);
  EXPECT_EQ(m.apply(request("r5", "g1/1/cusum/0", am::ActionKind::Shelve, kNow), kNow).refusal,
            am::Refusal::BadRequest);  // ends now
  EXPECT_EQ(m.apply(request("r6", "g1/1/cusum/0", am::ActionKind::Shelve, kNow + 8 * 86400 * kS), kNow).refusal,
            am::Refusal::BadRequest);  // longer than a week
  EXPECT_EQ(m.apply(request("r7", "g1/1/cusum/0", am::ActionKind::Unshelve), kNow).refusal,
            am::Refusal::NotApplicable);
  auto control = request("r8", "g1/1/cusum/0", am::ActionKind::Acknowledge);
  control.reason = "bad\nline";
  EXPECT_EQ(m.apply(control, kNow).refusal, am::Refusal::BadRequest);
  auto until_on_ack = request("r9", "g1/1/cusum/0", am::ActionKind::Acknowledge, kNow + kS);
  EXPECT_EQ(m.apply(until_on_ack, kNow).refusal, am::Refusal::BadRequest);
  const auto& c = m.counters();
  EXPECT_EQ(c.applied, 0u);
  EXPECT_EQ(c.refused.at(am::Refusal::UnknownAlarm), 2u);
  EXPECT_EQ(c.refused.at(am::Refusal::BadRequest), 6u);
  EXPECT_EQ(c.refused.at(am::Refusal::NotApplicable), 1u);
  EXPECT_FALSE(m.flags("g1/1/cusum/0").acknowledged);
  EXPECT_FALSE(m.flags("g1/1/cusum/0").shelved);
}

TEST(AlarmManagement, RepeatedRequestIdGivesItsFirstOutcome) {
  am::AlarmManager m;
  m.on_event(event("g1/1/cusum/0", am::EventState::Raised, kT0));
  ASSERT_TRUE(m.apply(request("r1", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow).applied);
  const auto again = m.apply(request("r1", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow);
  EXPECT_TRUE(again.applied);
  EXPECT_TRUE(again.repeated);
  EXPECT_EQ(m.counters().applied, 1u);
  EXPECT_EQ(m.counters().repeated, 1u);
}

TEST(AlarmManagement, ShelvingCoversTheSourceAndExpiresOnTheWallClock) {
  am::AlarmManager m;
  m.on_event(event("g1/3/cusum/0", am::EventState::Raised, kT0));
  const auto o = m.apply(request("s1", "g1/3/cusum/0", am::ActionKind::Shelve, kNow + 300 * kS), kNow);
  ASSERT_TRUE(o.applied) << o.error;
  EXPECT_TRUE(o.shelved);
  EXPECT_EQ(m.health("g1", kT0).shelved, 1u);
  // The same source raised anew (a new id) is still shelved: published and recorded, flagged.
  m.on_event(event("g1/3/cusum/0", am::EventState::Cleared, kT0));
  EXPECT_TRUE(m.on_event(event("g1/3/cusum/1", am::EventState::Raised, kT0 + 600 * kS)).shelved);
  EXPECT_FALSE(m.on_event(event("g1/4/cusum/0", am::EventState::Raised, kT0 + 600 * kS)).shelved);
  // Nothing expires before the end; at the end exactly one shelving is lifted, once.
  EXPECT_TRUE(m.expire(kNow + 299 * kS).empty());
  const auto expired = m.expire(kNow + 300 * kS);
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired[0].source, "g1/3/cusum");
  EXPECT_EQ(expired[0].alarm_id, "g1/3/cusum/0");
  EXPECT_EQ(expired[0].asset_group, "g1");
  EXPECT_EQ(expired[0].until_ns, kNow + 300 * kS);
  EXPECT_TRUE(m.expire(kNow + 301 * kS).empty());
  EXPECT_FALSE(m.flags("g1/3/cusum/1").shelved);
  EXPECT_EQ(m.health("g1", kT0 + 600 * kS).shelved, 0u);
  EXPECT_EQ(m.counters().expired, 1u);
}

TEST(AlarmManagement, UnshelveLiftsAtOnce) {
  am::AlarmManager m;
  m.on_event(event("g1/3/cusum/0", am::EventState::Raised, kT0));
  ASSERT_TRUE(m.apply(request("s1", "g1/3/cusum/0", am::ActionKind::Shelve, kNow + 300 * kS), kNow).applied);
  const auto o = m.apply(request("u1", "g1/3/cusum/0", am::ActionKind::Unshelve), kNow + kS);
  ASSERT_TRUE(o.applied) << o.error;
  EXPECT_FALSE(o.shelved);
  EXPECT_TRUE(m.expire(kNow + 400 * kS).empty());
}

TEST(AlarmManagement, FloodCountsRaisesInTenMinutesOfDataTime) {
  am::AlarmManager m;
  // 11 raises 50 s apart: 0 .. 500 s, all inside (t - 600 s, t] at t = 500 s: a flood (> 10).
  for (int i = 0; i < 11; ++i) {
    m.on_event(event("g1/" + std::to_string(i + 1) + "/cusum/0", am::EventState::Raised, kT0 + i * 50 * kS));
  }
  auto h = m.health("g1", kT0 + 500 * kS);
  EXPECT_EQ(h.alarms_per_10_min, 11u);
  EXPECT_TRUE(h.flood);
  // At t = 600 s the first raise (t = 0) has left the window: 10, no flood.
  h = m.health("g1", kT0 + 600 * kS);
  EXPECT_EQ(h.alarms_per_10_min, 10u);
  EXPECT_FALSE(h.flood);
  // Escalations are not new alarms; another group's raises are not counted.
  m.on_event(event("g1/1/cusum/0", am::EventState::Escalated, kT0));
  m.on_event(event("g2/1/cusum/0", am::EventState::Raised, kT0 + 500 * kS, "g2"));
  EXPECT_EQ(m.health("g1", kT0 + 500 * kS).alarms_per_10_min, 11u);
  EXPECT_EQ(m.health("g2", kT0 + 500 * kS).alarms_per_10_min, 1u);
}

TEST(AlarmManagement, StandingAlarmsAreOpenLongerThanADay) {
  am::AlarmManager m;
  m.on_event(event("g1/1/cusum/0", am::EventState::Raised, kT0));
  m.on_event(event("g1/2/cusum/0", am::EventState::Raised, kT0 + 3600 * kS));
  const std::int64_t day = 86400 * kS;
  EXPECT_EQ(m.health("g1", kT0 + day).standing, 0u);          // exactly 24 h: not more
  EXPECT_EQ(m.health("g1", kT0 + day + kS).standing, 1u);
  EXPECT_EQ(m.health("g1", kT0 + day + 3601 * kS).standing, 2u);
  m.on_event(event("g1/1/cusum/0", am::EventState::Cleared, kT0));
  EXPECT_EQ(m.health("g1", kT0 + day + 3601 * kS).standing, 1u);
}

TEST(AlarmManagement, ChatteringIsThreeRaisesOfOneSourceWithinAMinute) {
  am::AlarmManager m;
  // Source g1/1/cusum: raised and cleared at 0, 20, 40 s (three cycles in 60 s): chattering.
  for (int i = 0; i < 3; ++i) {
    const std::string id = "g1/1/cusum/" + std::to_string(i);
    m.on_event(event(id, am::EventState::Raised, kT0 + i * 20 * kS));
    m.on_event(event(id, am::EventState::Cleared, kT0 + i * 20 * kS));
  }
  // Source g1/2/cusum: three cycles 30 s apart (0, 30, 60 s): never three within a minute.
  for (int i = 0; i < 3; ++i) {
    const std::string id = "g1/2/cusum/" + std::to_string(i);
    m.on_event(event(id, am::EventState::Raised, kT0 + i * 30 * kS));
    m.on_event(event(id, am::EventState::Cleared, kT0 + i * 30 * kS));
  }
  EXPECT_EQ(m.health("g1", kT0 + 40 * kS).chattering, 1u);
  EXPECT_EQ(m.health("g1", kT0 + 60 * kS).chattering, 0u);  // g1/1's first raise left (0, 60]
  EXPECT_EQ(m.health("g1", kT0 + 59 * kS).chattering, 1u);
}

TEST(AlarmManagement, ActionNamesRoundTrip) {
  for (auto k : {am::ActionKind::Acknowledge, am::ActionKind::Shelve, am::ActionKind::Unshelve}) {
    EXPECT_EQ(am::parse_action(am::to_string(k)), k);
  }
  EXPECT_FALSE(am::parse_action("ack").has_value());
  EXPECT_EQ(am::source_of("g1/3/cusum/12"), "g1/3/cusum");
  EXPECT_EQ(am::source_of("plain"), "plain");
}
