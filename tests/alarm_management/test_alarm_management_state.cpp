// AlarmManager's checkpoint round trip: what a restarted alarm-recommender restores is what it held, so an
// acknowledged alarm stays acknowledged, a shelving ends at the same wall-clock time, a re-delivered request gets
// its first outcome, the health figures are the same, and the republished events do not undo any of it.
#include "alarm_management_fixtures.hpp"

#include "causal/alarm_management/alarm_management.hpp"
#include "causal/estimation/state_archive.hpp"
#include "same_fields.hpp"

#include <gtest/gtest.h>

#include <string>

namespace am = causal::alarm_management;
using namespace causal::alarm_management::test;

namespace {

// Three alarms: a acknowledged, b shelved until kNow + 60 s, c cleared; chatter on c's source.
am::AlarmManager held() {
  am::AlarmManager m;
  m.on_event(event("g1/1/cusum/0", am::EventState::Raised, kT0));
  m.on_event(event("g1/2/nis/0", am::EventState::Raised, kT0 + kS));
  for (int i = 0; i < 3; ++i) {
    const std::string id = "g1/3/drift/" + std::to_string(i);
    m.on_event(event(id, am::EventState::Raised, kT0 + 2 * kS + i * 10 * kS));
    m.on_event(event(id, am::EventState::Cleared, kT0 + 2 * kS + i * 10 * kS));
  }
  EXPECT_TRUE(m.apply(request("r1", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow).applied);
  EXPECT_TRUE(m.apply(request("r2", "g1/2/nis/0", am::ActionKind::Shelve, kNow + 60 * kS), kNow).applied);
  EXPECT_FALSE(m.apply(request("r3", "g1/9/none/0", am::ActionKind::Acknowledge), kNow).applied);
  return m;
}

am::AlarmManager round_trip(const am::AlarmManager& m) {
  causal::estimation::StateWriter out;
  m.save(out);
  causal::estimation::StateReader in(out.bytes());
  am::AlarmManager restored;
  restored.restore(in);
  EXPECT_TRUE(in.at_end());
  return restored;
}

void expect_same_health(const am::GroupHealth& a, const am::GroupHealth& b) {
  EXPECT_SAME_FIELDS(a, b, unacknowledged, shelved, alarms_per_10_min, flood, standing, chattering, open);
}

}  // namespace

TEST(AlarmManagementState, RoundTripKeepsAcknowledgementShelvingAndHealth) {
  const am::AlarmManager before = held();
  am::AlarmManager after = round_trip(before);
  EXPECT_TRUE(after.flags("g1/1/cusum/0").acknowledged);
  EXPECT_TRUE(after.flags("g1/2/nis/5").shelved);  // the source is shelved, any of its raises
  const auto h = after.health("g1", kT0 + 30 * kS);
  expect_same_health(h, before.health("g1", kT0 + 30 * kS));
  EXPECT_EQ(h.open, 2u);
  EXPECT_EQ(h.unacknowledged, 1u);
  EXPECT_EQ(h.shelved, 1u);
  EXPECT_EQ(h.alarms_per_10_min, 5u);
  EXPECT_EQ(h.chattering, 1u);
  // The counters are this process's: a restored manager starts at zero.
  EXPECT_EQ(after.counters().applied, 0u);
  // A second acknowledge is still refused; a cleared alarm is still known.
  EXPECT_EQ(after.apply(request("r4", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow).refusal,
            am::Refusal::NotApplicable);
  EXPECT_TRUE(after.apply(request("r5", "g1/3/drift/2", am::ActionKind::Acknowledge), kNow).applied);
}

TEST(AlarmManagementState, ShelvingExpiresAtTheSameTimeAfterARestore) {
  am::AlarmManager after = round_trip(held());
  EXPECT_TRUE(after.expire(kNow + 60 * kS - 1).empty());
  const auto expired = after.expire(kNow + 60 * kS);
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired[0].source, "g1/2/nis");
  EXPECT_EQ(expired[0].alarm_id, "g1/2/nis/0");
  EXPECT_EQ(expired[0].until_ns, kNow + 60 * kS);
  EXPECT_FALSE(after.flags("g1/2/nis/0").shelved);
}

TEST(AlarmManagementState, ReDeliveredRequestGetsItsFirstOutcome) {
  am::AlarmManager after = round_trip(held());
  const auto again = after.apply(request("r1", "g1/1/cusum/0", am::ActionKind::Acknowledge), kNow);
  EXPECT_TRUE(again.repeated);
  EXPECT_TRUE(again.applied);
  const auto refused = after.apply(request("r3", "g1/9/none/0", am::ActionKind::Acknowledge), kNow);
  EXPECT_TRUE(refused.repeated);
  EXPECT_EQ(refused.refusal, am::Refusal::UnknownAlarm);
  EXPECT_EQ(after.counters().repeated, 2u);
  EXPECT_EQ(after.counters().applied, 0u);
}

TEST(AlarmManagementState, RepublishedEventsKeepTheAcknowledgementAndCountNoNewRaise) {
  am::AlarmManager after = round_trip(held());
  const auto before = after.health("g1", kT0 + 30 * kS);
  EXPECT_TRUE(after.on_republished(event("g1/1/cusum/0", am::EventState::Raised, kT0)).acknowledged);
  EXPECT_TRUE(after.on_republished(event("g1/2/nis/0", am::EventState::Raised, kT0 + kS)).shelved);
  after.on_republished(event("g1/3/drift/2", am::EventState::Cleared, kT0 + 22 * kS));
  expect_same_health(after.health("g1", kT0 + 30 * kS), before);
  // An event the checkpoint did not hold (the process died between the engine checkpoint and this one) is new.
  EXPECT_FALSE(after.on_republished(event("g1/4/cusum/0", am::EventState::Raised, kT0 + 25 * kS)).acknowledged);
  EXPECT_EQ(after.health("g1", kT0 + 30 * kS).open, 3u);
  // A later event of an acknowledged alarm in a new state (it cleared meanwhile) is applied.
  after.on_republished(event("g1/1/cusum/0", am::EventState::Cleared, kT0));
  EXPECT_EQ(after.health("g1", kT0 + 30 * kS).open, 2u);
}

TEST(AlarmManagementState, OtherSectionOrTruncatedIsRefused) {
  causal::estimation::StateWriter other;
  other.begin("alarm_management", 2);
  causal::estimation::StateReader wrong_version(other.bytes());
  am::AlarmManager m;
  EXPECT_THROW(m.restore(wrong_version), causal::estimation::StateError);
  causal::estimation::StateWriter out;
  held().save(out);
  causal::estimation::StateReader truncated(out.bytes().substr(0, out.bytes().size() - 3));
  EXPECT_THROW(m.restore(truncated), causal::estimation::StateError);
  // A refused restore leaves the manager as it was (empty).
  EXPECT_EQ(m.health("g1", kT0).open, 0u);
}
