// causal::dds::IndexLedger (common/dds/src/index_ledger.cpp): exactly-once bookkeeping of stream indices,
// checked against a plain std::set of the same indices (independent truth).
#include "causal/dds/index_ledger.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

using causal::dds::IndexLedger;
using causal::dds::IndexRange;
using causal::dds::describe_ranges;

TEST(IndexLedger, InOrderStreamIsOneRunWithoutGaps) {
  IndexLedger l;
  for (std::uint64_t n = 5; n < 1005; ++n) EXPECT_TRUE(l.record(n));
  EXPECT_EQ(l.count(), 1000u);
  EXPECT_EQ(*l.lowest(), 5u);
  EXPECT_EQ(*l.highest(), 1004u);
  EXPECT_TRUE(l.missing().empty());
  EXPECT_EQ(l.missing_count(), 0u);
  for (std::uint64_t n : {5u, 500u, 1004u}) EXPECT_FALSE(l.record(n)) << n;
  EXPECT_EQ(l.count(), 1000u);
}

TEST(IndexLedger, GapsAreReportedAndFilledLateArrivalsCloseThem) {
  IndexLedger l;
  for (std::uint64_t n = 0; n < 120; ++n) l.record(n);
  for (std::uint64_t n = 132; n < 140; ++n) l.record(n);
  l.record(141);
  EXPECT_EQ(l.missing(), (std::vector<IndexRange>{{120, 131}, {140, 140}}));
  EXPECT_EQ(l.missing_count(), 13u);
  EXPECT_EQ(describe_ranges(l.missing()), "120..131, 140");
  EXPECT_TRUE(l.record(140));  // late, fills the single gap and joins two runs
  EXPECT_TRUE(l.record(120));  // extends a run upwards
  EXPECT_TRUE(l.record(131));  // extends a run downwards
  EXPECT_EQ(l.missing(), (std::vector<IndexRange>{{121, 130}}));
  EXPECT_FALSE(l.contains(125));
  EXPECT_TRUE(l.contains(131));
  EXPECT_TRUE(l.contains(141));
  EXPECT_FALSE(l.contains(142));
}

TEST(IndexLedger, RandomArrivalsAgreeWithAPlainSet) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::uint64_t> pick(0, 300);
  IndexLedger l;
  std::set<std::uint64_t> truth;
  for (int i = 0; i < 2000; ++i) {
    const std::uint64_t n = pick(rng);
    EXPECT_EQ(l.record(n), truth.insert(n).second) << n;
    if (i % 97 == 0) {
      std::vector<IndexRange> gaps;
      for (std::uint64_t m = *truth.begin(); m <= *truth.rbegin(); ++m) {
        if (truth.count(m) > 0) continue;
        if (!gaps.empty() && gaps.back().last + 1 == m) gaps.back().last = m;
        else gaps.push_back({m, m});
      }
      EXPECT_EQ(l.missing(), gaps) << "after " << i;
    }
  }
  EXPECT_EQ(l.count(), truth.size());
  for (std::uint64_t m = 0; m <= 301; ++m) EXPECT_EQ(l.contains(m), truth.count(m) > 0) << m;
}

TEST(IndexLedger, DescribeRangesShortensLongLists) {
  std::vector<IndexRange> r;
  for (std::uint64_t i = 0; i < 13; ++i) r.push_back({10 * i, 10 * i + (i % 2)});
  EXPECT_EQ(describe_ranges(r, 3), "0, 10..11, 20 and 10 more");
  EXPECT_EQ(describe_ranges({}), "");
  IndexLedger empty;
  EXPECT_FALSE(empty.lowest().has_value());
  EXPECT_EQ(empty.missing_count(), 0u);
}
