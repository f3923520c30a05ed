// causal-recorder's ReceptionLedger: which writers were publishing when a suspension began and were never heard
// after it. Times in seconds on a made-up system clock; the verdicts are worked out by hand.
#include "reception_ledger.hpp"

#include <gtest/gtest.h>

using causal::recorder::ReceptionLedger;

namespace {
constexpr std::int64_t kS = 1'000'000'000;
// A 30 s stop from t = 100 s to t = 130 s; writers heard within 5 s (the lease) before it were publishing; news
// from after it is what arrived at or after 129 s (the resume minus 1 s).
std::vector<causal::recorder::SilentWriter> silent(const ReceptionLedger& ledger) {
  return ledger.silent_after(100 * kS, 5 * kS, 129 * kS);
}
}  // namespace

TEST(ReceptionLedger, AWriterHeardAgainAfterTheStopIsNotSilent) {
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "conditions-writer", 99 * kS);
  ledger.note("conditions", "estimator", "conditions-writer", 131 * kS);  // the re-sent history ring after the re-match
  EXPECT_TRUE(silent(ledger).empty());
}

TEST(ReceptionLedger, OneSilentWriterIsNamedEvenWhenAnotherIsHeardAgain) {
  // The freeze seen on shared memory: alarm-recommender reaches the recorder again, the estimator never does.
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "conditions-writer", 99 * kS);
  ledger.note("alarms", "recommender", "alarm-writer", 98 * kS);
  ledger.note("alarms", "recommender", "alarm-writer", 130 * kS);
  const auto s = silent(ledger);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].topic, "conditions");
  EXPECT_EQ(s[0].participant, "estimator");
  EXPECT_EQ(s[0].writer, "conditions-writer");
  EXPECT_EQ(s[0].last_reception_ns, 99 * kS);
  EXPECT_EQ(ledger.heard_after(129 * kS), 1u);  // the recommender
}

TEST(ReceptionLedger, SamplesThatArrivedBeforeTheStopAreNotNewsFromAfterIt) {
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "conditions-writer", 99 * kS);
  ledger.note("conditions", "estimator", "conditions-writer", 128 * kS + kS / 2);  // 0.5 s before the margin: still before the resume
  ASSERT_EQ(silent(ledger).size(), 1u);
  ledger.note("conditions", "estimator", "conditions-writer", 129 * kS);  // at the margin: after it
  EXPECT_TRUE(silent(ledger).empty());
}

TEST(ReceptionLedger, AWriterQuietLongBeforeTheStopWasNotPublishing) {
  // Last heard 6 s before the stop (more than the lease): done before it, so nothing of it can be missing.
  ReceptionLedger ledger;
  ledger.note("conditions", "first-estimator", "w", 94 * kS);
  ledger.note("conditions", "second-estimator", "w", 95 * kS);  // exactly one lease before: publishing
  const auto s = silent(ledger);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].participant, "second-estimator");
}

TEST(ReceptionLedger, TheLatestReceptionCountsWhateverTheOrderOfNotes) {
  // Takes from several readers interleave: an older reception noted last must not move a writer's time back.
  ReceptionLedger ledger;
  ledger.note("factors", "estimator", "factors-writer", 131 * kS);
  ledger.note("factors", "estimator", "factors-writer", 99 * kS);
  EXPECT_TRUE(silent(ledger).empty());
  EXPECT_FALSE(ledger.empty());
}

TEST(ReceptionLedger, SilentWritersComeOrderedByTopicThenWriter) {
  ReceptionLedger ledger;
  ledger.note("factors", "b", "w", 99 * kS);
  ledger.note("conditions", "b", "w", 99 * kS);
  ledger.note("conditions", "a", "w", 99 * kS);
  const auto s = silent(ledger);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].topic + "/" + s[0].participant, "conditions/a");
  EXPECT_EQ(s[1].topic + "/" + s[1].participant, "conditions/b");
  EXPECT_EQ(s[2].topic + "/" + s[2].participant, "factors/b");
}

TEST(ReceptionLedger, TheQuietWritersOfAnUnreachableParticipantAreNamedWithIt) {
  // The other freeze seen on shared memory: alarm-recommender never reached the recorder again. Its status writer
  // was publishing at the stop; its alarm writer had been quiet for a minute, but what it raised meanwhile is just
  // as missing. The estimator came back, and a quiet writer of its own is not named.
  ReceptionLedger ledger;
  ledger.note("asset_status", "recommender", "status-writer", 99 * kS);
  ledger.note("alarms", "recommender", "alarm-writer", 40 * kS);
  ledger.note("conditions", "estimator", "conditions-writer", 99 * kS);
  ledger.note("conditions", "estimator", "conditions-writer", 131 * kS);
  ledger.note("whatif", "estimator", "whatif-writer", 40 * kS);
  const auto s = silent(ledger);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].topic + "/" + s[0].writer, "alarms/alarm-writer");
  EXPECT_EQ(s[1].topic + "/" + s[1].writer, "asset_status/status-writer");
  EXPECT_EQ(ledger.heard_after(129 * kS), 1u);
}
