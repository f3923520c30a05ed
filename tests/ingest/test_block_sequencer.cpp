// The frame stream sensor-ingest makes of the source's blocks: gap-free frame sequence numbers, sample
// indices counting every published sample, discontinuities exactly where the source skipped, rejections for
// duplicates, overlaps and layout changes. Expected values are worked out by hand from the block times.
#include <gtest/gtest.h>

#include "block_sequencer.hpp"

using causal::ingest::BlockSequencer;
using causal::ingest::IngestBlock;
using causal::ingest::RejectReason;

namespace {

constexpr double kRate = 1000.0;  // 1 ms per sample
constexpr std::int64_t kMs = 1000000;

IngestBlock block(std::uint64_t sequence, std::int64_t t0_ns, std::size_t n = 10, const std::string& group = "g1") {
  IngestBlock b;
  b.asset_group = group;
  b.channels = {"a", "b"};
  b.sample_rate_hz = kRate;
  b.t0_ns = t0_ns;
  b.sequence = sequence;
  b.samples_per_channel = n;
  b.samples.assign(2 * n, 0.0);
  return b;
}

// An admitted block that starts a new segment: a discontinuity at snapshot index `snapshot`, frame `sequence`.
template <typename Admission>
void expect_new_segment(const Admission& a, std::uint64_t snapshot, std::uint64_t sequence) {
  ASSERT_TRUE(a.plan) << a.detail;
  EXPECT_TRUE(a.plan->discontinuity);
  EXPECT_EQ(a.plan->snapshot_index, snapshot);
  EXPECT_EQ(a.plan->sequence, sequence);
}

}  // namespace

TEST(BlockSequencer, ContiguousBlocksGiveGapFreeFrames) {
  BlockSequencer s;
  for (std::uint64_t i = 0; i < 5; ++i) {
    const auto a = s.admit(block(100 + i, static_cast<std::int64_t>(i) * 10 * kMs));
    ASSERT_TRUE(a.plan) << a.detail;
    EXPECT_EQ(a.plan->sequence, i);
    EXPECT_EQ(a.plan->first_sample_index, 10 * i);
    EXPECT_EQ(a.plan->snapshot_index, 0u);
    EXPECT_EQ(a.plan->discontinuity, i == 0);
  }
}

TEST(BlockSequencer, SourceSequenceGapIsADiscontinuityNotAFrameGap) {
  BlockSequencer s;
  ASSERT_TRUE(s.admit(block(0, 0)).plan);
  const auto a = s.admit(block(3, 30 * kMs));  // blocks 1 and 2 never arrived
  ASSERT_NO_FATAL_FAILURE(expect_new_segment(a, 1, 1));
  EXPECT_EQ(a.plan->first_sample_index, 10u);
}

TEST(BlockSequencer, TimeGapOverGapFactorIsADiscontinuity) {
  BlockSequencer s(1.5);
  ASSERT_TRUE(s.admit(block(0, 0)).plan);
  // Previous block ends at 10 ms (last sample at 9 ms). Next starts at 10.4 ms: 1.4 periods after it: no gap.
  const auto jitter = s.admit(block(1, 10 * kMs + 400000));
  ASSERT_TRUE(jitter.plan);
  EXPECT_FALSE(jitter.plan->discontinuity);
  // Previous ends at 20.4 ms (last sample 19.4 ms); 21 ms is 1.6 periods after the last sample: a gap.
  expect_new_segment(s.admit(block(2, 21 * kMs)), 1, 2);
}

TEST(BlockSequencer, DuplicatesOverlapsAndLayoutChangesAreRejectedWithoutConsumingNumbers) {
  BlockSequencer s;
  ASSERT_TRUE(s.admit(block(0, 0)).plan);
  auto dup = s.admit(block(0, 0));
  EXPECT_FALSE(dup.plan);
  EXPECT_EQ(dup.reason, RejectReason::Duplicate);
  auto overlap = s.admit(block(1, 5 * kMs));  // starts before the previous block (0..9 ms) ended
  EXPECT_FALSE(overlap.plan);
  EXPECT_EQ(overlap.reason, RejectReason::OutOfOrder);
  IngestBlock three = block(1, 10 * kMs);
  three.channels.push_back("c");
  three.samples.assign(30, 0.0);
  auto layout = s.admit(three);
  EXPECT_FALSE(layout.plan);
  EXPECT_EQ(layout.reason, RejectReason::LayoutChange);
  const auto next = s.admit(block(1, 10 * kMs));
  ASSERT_TRUE(next.plan);
  EXPECT_EQ(next.plan->sequence, 1u);
  EXPECT_EQ(next.plan->first_sample_index, 10u);
  EXPECT_FALSE(next.plan->discontinuity);
}

TEST(BlockSequencer, RestartedSourceAndNewSegmentsAreDiscontinuities) {
  BlockSequencer s;
  ASSERT_TRUE(s.admit(block(7, 0)).plan);
  const auto restart = s.admit(block(0, 60 * kMs));  // sequence back to 0, time went on
  ASSERT_TRUE(restart.plan);
  EXPECT_TRUE(restart.plan->discontinuity);
  EXPECT_EQ(restart.plan->snapshot_index, 1u);
  IngestBlock closing = block(1, 70 * kMs);
  closing.end_of_segment = true;
  const auto c = s.admit(closing);
  ASSERT_TRUE(c.plan);
  EXPECT_FALSE(c.plan->discontinuity);
  expect_new_segment(s.admit(block(2, 80 * kMs)), 2, 3);  // contiguous in time, but after end_of_segment
}

TEST(BlockSequencer, AssetGroupsAreCountedSeparately) {
  BlockSequencer s;
  ASSERT_EQ(s.admit(block(0, 0, 10, "g1")).plan->sequence, 0u);
  ASSERT_EQ(s.admit(block(0, 0, 10, "g2")).plan->sequence, 0u);
  ASSERT_EQ(s.admit(block(1, 10 * kMs, 10, "g1")).plan->sequence, 1u);
  EXPECT_EQ(s.groups(), 2u);
}

// A restarted sensor-ingest continues the numbering a previous run left (ResumePoint), so its
// frames are never taken for ones the estimator already processed.
TEST(BlockSequencer, ResumedGroupContinuesNumberingWithANewSegment) {
  BlockSequencer first;
  for (std::uint64_t i = 0; i < 4; ++i) ASSERT_TRUE(first.admit(block(i, static_cast<std::int64_t>(i) * 10 * kMs)).plan);
  const auto point = first.resume_point("g1");
  ASSERT_TRUE(point);
  EXPECT_EQ(point->next_sequence, 4u);
  EXPECT_EQ(point->next_sample_index, 40u);
  EXPECT_FALSE(first.resume_point("other"));

  BlockSequencer restarted;
  restarted.resume("g1", *point);
  EXPECT_TRUE(restarted.knows("g1"));
  // The restarted source counts from 0 again, later in time.
  const auto a = restarted.admit(block(0, 3600 * 1000 * kMs));
  ASSERT_TRUE(a.plan) << a.detail;
  EXPECT_EQ(a.plan->sequence, 4u);
  EXPECT_EQ(a.plan->first_sample_index, 40u);
  EXPECT_EQ(a.plan->snapshot_index, point->snapshot_index + 1);
  EXPECT_TRUE(a.plan->discontinuity);
  EXPECT_NE(a.plan->why.find("restarted"), std::string::npos);
  const auto b = restarted.admit(block(1, 3600 * 1000 * kMs + 10 * kMs));
  ASSERT_TRUE(b.plan);
  EXPECT_EQ(b.plan->sequence, 5u);
  EXPECT_FALSE(b.plan->discontinuity);
  // Another channel layout after the restart is refused as before.
  auto wide = block(2, 3600 * 1000 * kMs + 20 * kMs);
  wide.channels = {"a", "b", "c"};
  EXPECT_EQ(restarted.admit(wide).reason, RejectReason::LayoutChange);
}

// Blocks lost across a restart (sensor-ingest killed while the source went on, the source not queueing: stdin,
// UDP): the resume point keeps the source's last sequence, so the first block after the restart tells how many never
// came. Their frame numbers stay unused (the estimator counts lost frames) and, with one segment per block, their
// snapshot and sample indices too (the recorder's gap and the alarm engine name the same snapshots).
TEST(BlockSequencer, BlocksMissedAcrossARestartAreSkippedInTheNumbering) {
  BlockSequencer first;
  for (std::uint64_t i = 0; i < 4; ++i) {
    auto b = block(100 + i, static_cast<std::int64_t>(i) * 10 * kMs);
    b.end_of_segment = true;
    ASSERT_TRUE(first.admit(b).plan);
  }
  const auto point = first.resume_point("g1");
  ASSERT_TRUE(point);
  EXPECT_TRUE(point->has_source_sequence);
  EXPECT_EQ(point->last_source_sequence, 103u);
  EXPECT_EQ(point->snapshot_index, 3u);

  BlockSequencer restarted;
  restarted.resume("g1", *point);
  auto again = block(103, 30 * kMs);  // the last block before the restart, once more
  again.end_of_segment = true;
  EXPECT_EQ(restarted.admit(again).reason, RejectReason::Duplicate);
  auto next = block(107, 70 * kMs);  // 104..106 never came
  next.end_of_segment = true;
  const auto a = restarted.admit(next);
  ASSERT_TRUE(a.plan) << a.detail;
  EXPECT_EQ(a.plan->missed, 3u);
  EXPECT_EQ(a.plan->sequence, 7u);             // frames 4..6 unused
  EXPECT_EQ(a.plan->snapshot_index, 7u);       // snapshots 4..6 skipped: 3 + 3 + the new segment
  EXPECT_EQ(a.plan->first_sample_index, 70u);  // 40 + 3 blocks of 10
  EXPECT_TRUE(a.plan->discontinuity);
  EXPECT_NE(a.plan->why.find("source blocks 104..106 never reached sensor-ingest"), std::string::npos) << a.plan->why;

  // The source restarted too (its sequence back at 0): nothing is known lost.
  BlockSequencer both;
  both.resume("g1", *point);
  const auto z = both.admit(block(0, 3600 * 1000 * kMs));
  ASSERT_TRUE(z.plan);
  EXPECT_EQ(z.plan->missed, 0u);
  EXPECT_EQ(z.plan->sequence, 4u);
  // The next block after the source's own continuation: nothing missed.
  BlockSequencer cont;
  cont.resume("g1", *point);
  auto c = block(104, 40 * kMs);
  c.end_of_segment = true;
  const auto ca = cont.admit(c);
  ASSERT_TRUE(ca.plan);
  EXPECT_EQ(ca.plan->missed, 0u);
  EXPECT_EQ(ca.plan->sequence, 4u);
  EXPECT_EQ(ca.plan->snapshot_index, 4u);
}
