// causal-recorder's ReceptionLedger: which writers were publishing when a suspension began and were never heard
// after it, and what the writers heard again published meanwhile that never arrived. Times in seconds on a
// made-up system clock; the verdicts are worked out by hand.
#include "reception_ledger.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using causal::recorder::ReceptionLedger;

namespace {
constexpr std::int64_t kS = 1'000'000'000;
// A 30 s stop from t = 100 s to t = 130 s; writers heard within 5 s (the lease) before it were publishing; news
// from after it is what arrived at or after 129 s (the resume minus 1 s).
std::vector<causal::recorder::SilentWriter> silent(const ReceptionLedger& ledger) {
  return ledger.silent_after(100 * kS, 5 * kS, 129 * kS);
}
// "topic/participant/writer" of each silent writer, in the ledger's order.
std::vector<std::string> named(const std::vector<causal::recorder::SilentWriter>& writers) {
  std::vector<std::string> out;
  for (const auto& w : writers) out.push_back(w.topic + "/" + w.participant + "/" + w.writer);
  return out;
}
using Names = std::vector<std::string>;
}  // namespace

TEST(ReceptionLedger, AWriterHeardAgainAfterTheStopIsNotSilent) {
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "w", 1, 99 * kS);
  ledger.note("conditions", "estimator", "w", 2, 131 * kS);  // the re-sent history ring after the re-match
  EXPECT_TRUE(silent(ledger).empty());
}

TEST(ReceptionLedger, OneSilentWriterIsNamedEvenWhenAnotherIsHeardAgain) {
  // The freeze seen on shared memory: alarm-recommender reaches the recorder again, the estimator never does.
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "w", 1, 99 * kS);
  ledger.note("alarms", "recommender", "w", 1, 98 * kS);
  ledger.note("alarms", "recommender", "w", 2, 130 * kS);
  const auto s = silent(ledger);
  EXPECT_EQ(named(s), (Names{"conditions/estimator/w"}));
  EXPECT_EQ(s.at(0).last_reception_ns, 99 * kS);
  EXPECT_EQ(ledger.heard_after(129 * kS), 1u);  // the recommender
}

TEST(ReceptionLedger, SamplesThatArrivedBeforeTheStopAreNotNewsFromAfterIt) {
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "w", 1, 99 * kS);
  ledger.note("conditions", "estimator", "w", 2, 128 * kS + kS / 2);  // 0.5 s before 129 s: before the resume
  EXPECT_EQ(silent(ledger).size(), 1u);
  ledger.note("conditions", "estimator", "w", 3, 129 * kS);  // at the margin: after it
  EXPECT_TRUE(silent(ledger).empty());
}

TEST(ReceptionLedger, AWriterQuietLongBeforeTheStopWasNotPublishing) {
  // The first estimator was last heard 6 s before the stop (more than the lease): done before it, so nothing of it
  // can be missing. The second one exactly one lease before it: publishing.
  ReceptionLedger ledger;
  ledger.note("conditions", "first-estimator", "w", 1, 94 * kS);
  ledger.note("conditions", "second-estimator", "w", 1, 95 * kS);
  EXPECT_EQ(named(silent(ledger)), (Names{"conditions/second-estimator/w"}));
}

TEST(ReceptionLedger, TheLatestReceptionCountsWhateverTheOrderOfNotes) {
  // Takes from several readers interleave: an older reception noted last must not move a writer's time back.
  ReceptionLedger ledger;
  ledger.note("factors", "estimator", "w", 2, 131 * kS);
  ledger.note("factors", "estimator", "w", 1, 99 * kS);
  EXPECT_TRUE(silent(ledger).empty());
  EXPECT_FALSE(ledger.empty());
}

TEST(ReceptionLedger, SilentWritersComeOrderedByTopicThenParticipant) {
  ReceptionLedger ledger;
  ledger.note("factors", "b", "w", 1, 99 * kS);
  ledger.note("conditions", "b", "w", 1, 99 * kS);
  ledger.note("conditions", "a", "w", 1, 99 * kS);
  EXPECT_EQ(named(silent(ledger)), (Names{"conditions/a/w", "conditions/b/w", "factors/b/w"}));
}

TEST(ReceptionLedger, TheQuietWritersOfAnUnreachableParticipantAreNamedWithIt) {
  // The other freeze seen on shared memory: alarm-recommender never reached the recorder again. Its status writer
  // was publishing at the stop; its alarm writer had been quiet for a minute, but what it raised meanwhile is just
  // as missing. The estimator came back, and a quiet writer of its own is not named.
  ReceptionLedger ledger;
  ledger.note("asset_status", "recommender", "status", 1, 99 * kS);
  ledger.note("alarms", "recommender", "alarm", 1, 40 * kS);
  ledger.note("conditions", "estimator", "conditions", 1, 99 * kS);
  ledger.note("conditions", "estimator", "conditions", 2, 131 * kS);
  ledger.note("whatif", "estimator", "whatif", 1, 40 * kS);
  EXPECT_EQ(named(silent(ledger)), (Names{"alarms/recommender/alarm", "asset_status/recommender/status"}));
  EXPECT_EQ(ledger.heard_after(129 * kS), 1u);
}

namespace {
// One writer, samples 1..10 received before a stop at t = 100 s (one per second up to 99 s), then the re-sent ring
// 15..18 and the live 19..20 after it: 11..14 were published during the stop and never arrived.
ReceptionLedger status_writer_across_a_stop() {
  ReceptionLedger ledger;
  for (std::uint64_t seq = 1; seq <= 10; ++seq) ledger.note("asset_status", "recommender", "w", seq, (89 + static_cast<std::int64_t>(seq)) * kS);
  for (std::uint64_t seq = 15; seq <= 20; ++seq) ledger.note("asset_status", "recommender", "w", seq, 130 * kS + static_cast<std::int64_t>(seq));
  return ledger;
}
}  // namespace

TEST(ReceptionLedger, SamplesPublishedDuringTheStopBeyondTheRingAreCountedBySequenceNumber) {
  const auto missed = status_writer_across_a_stop().missed_across(129 * kS);
  ASSERT_EQ(missed.size(), 1u);
  EXPECT_EQ(missed[0].topic, "asset_status");
  EXPECT_EQ(missed[0].count, 4u);
  ASSERT_EQ(missed[0].sequence_numbers.size(), 1u);
  EXPECT_EQ(missed[0].sequence_numbers[0], (causal::dds::IndexRange{11, 14}));
}

TEST(ReceptionLedger, GapsBeforeTheStopAreNotCountedAsMissedDuringIt) {
  // A late joiner's first history delivery has holes (other instances' older samples left the writer's rings):
  // not samples published during the stop. Received 3, 5, 7..10 first, then 11..12 after the stop: nothing missed.
  ReceptionLedger ledger;
  for (std::uint64_t seq : {3, 5, 7, 8, 9, 10}) ledger.note("prognosis", "recommender", "w", seq, 95 * kS);
  ledger.note("prognosis", "recommender", "w", 11, 131 * kS);
  ledger.note("prognosis", "recommender", "w", 12, 131 * kS);
  EXPECT_TRUE(ledger.missed_across(129 * kS).empty());
}

TEST(ReceptionLedger, ASampleTakenOutOfOrderAcrossTheStopStillCounts) {
  // A keyed reader hands out instance by instance: a sample received before the stop (seq 9, 98 s) may be taken
  // after samples received after it. The highest before the stop is still 10; 11..14 are missed.
  ReceptionLedger ledger;
  for (std::uint64_t seq : {1, 2, 3, 10}) ledger.note("asset_status", "recommender", "w", seq, 98 * kS);
  ledger.note("asset_status", "recommender", "w", 15, 131 * kS);
  ledger.note("asset_status", "recommender", "w", 9, 98 * kS);
  for (std::uint64_t seq : {4, 5, 6, 7, 8}) ledger.note("asset_status", "recommender", "w", seq, 97 * kS);
  const auto missed = ledger.missed_across(129 * kS);
  ASSERT_EQ(missed.size(), 1u);
  EXPECT_EQ(missed[0].count, 4u);
}

TEST(ReceptionLedger, AWriterNotHeardAgainIsLeftToTheSilenceVerdict) {
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "w", 1, 99 * kS);
  ledger.note("conditions", "estimator", "w", 5, 99 * kS);  // a hole before the stop, no reception after it
  EXPECT_TRUE(ledger.missed_across(129 * kS).empty());
  EXPECT_EQ(silent(ledger).size(), 1u);
}

TEST(ReceptionLedger, AWriterThatMissedNothingIsNotListed) {
  ReceptionLedger ledger = status_writer_across_a_stop();
  for (std::uint64_t seq = 11; seq <= 14; ++seq) ledger.note("asset_status", "recommender", "w", seq, 131 * kS);
  EXPECT_TRUE(ledger.missed_across(129 * kS).empty());
}

TEST(ReceptionLedger, AWriterFirstHeardAfterTheStopCountsFromItsFirstSampleWhenItsParticipantWasConnected) {
  // alarm-recommender's prognoses began during the stop (with the first degradation alarm): samples 1..4 left the
  // writer's ring before the re-match, 5..7 arrived. Its status writer was heard before: the recorder was matched.
  ReceptionLedger ledger;
  ledger.note("asset_status", "recommender", "status", 1, 99 * kS);
  ledger.note("asset_status", "recommender", "status", 2, 131 * kS);
  for (std::uint64_t seq : {5, 6, 7}) ledger.note("prognosis", "recommender", "prognosis", seq, 131 * kS);
  const auto missed = ledger.missed_across(129 * kS);
  ASSERT_EQ(missed.size(), 1u);
  EXPECT_EQ(missed[0].topic, "prognosis");
  EXPECT_EQ(missed[0].count, 4u);
  EXPECT_EQ(missed[0].sequence_numbers[0], (causal::dds::IndexRange{1, 4}));
}

TEST(ReceptionLedger, AParticipantFirstHeardAfterTheStopIsALateJoiner) {
  // A second estimator started during the stop: its history ring starts at 40, nothing of it was missed here.
  ReceptionLedger ledger;
  ledger.note("conditions", "estimator", "w", 1, 99 * kS);
  ledger.note("conditions", "estimator", "w", 2, 131 * kS);
  for (std::uint64_t seq : {40, 41, 42}) ledger.note("conditions", "estimator-2", "w", seq, 131 * kS);
  EXPECT_TRUE(ledger.missed_across(129 * kS).empty());
}
