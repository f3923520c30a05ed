// causal::dds::FactorSetAssembler (common/dds/src/factor_set_assembler.cpp): G per-outcome messages of one
// sample index -> one FactorSet, per stream in index order, each index at most once (re-sent and replayed
// indices are duplicates), bounded pending with a partial or drop policy, exact counters. The expected
// values come from the generating formulas below, not from the assembler.
#include "causal/dds/factor_set_assembler.hpp"
#include "factor_message_head.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

namespace {

using causal::dds::FactorMessage;
using causal::dds::FactorSet;
using causal::dds::FactorSetAssembler;
using causal::dds::IndexRange;
using Policy = FactorSetAssembler::IncompletePolicy;
using Status = FactorSetAssembler::AddStatus;

constexpr int kG = 3;
constexpr std::int64_t kT0 = 1'076'581'959'000'000'000LL;
constexpr std::int64_t kStep = 600'000'000'000LL;

// Outcome k (0-based) has 2 + k factors, so the outcome-major offsets are 0, 2, 5, 9.
int factor_count(int k) { return 2 + k; }
double value(std::uint64_t n, int k, int i) { return 0.1 * k + 0.01 * i + 1e-3 * static_cast<double>(n); }
double sd(std::uint64_t n, int k, int i) { return 0.5 + 1e-3 * (k + i) + 1e-6 * static_cast<double>(n); }

FactorMessage message(std::uint64_t n, int k, const std::string& group = "ims2",
                      causal_twin::TimeScale scale = causal_twin::CONDITION_LEVEL,
                      causal_twin::EstimateKind kind = causal_twin::FILTER) {
  const causal::test::FactorStreamId id{group, scale, kind, scale == causal_twin::CONDITION_LEVEL ? "rms" : ""};
  FactorMessage m = causal::test::factor_message_head(id, k, "b" + std::to_string(k + 1), kG, 1, n,
                                                      kT0 + static_cast<std::int64_t>(n) * kStep);
  const int d = factor_count(k);
  m.factors.resize(d);
  m.factor_std.resize(d);
  m.covariance = Eigen::MatrixXd::Identity(d, d) * (1.0 + k);
  for (int i = 0; i < d; ++i) {
    m.factor_names.push_back("x" + std::to_string(k + 1) + "_" + std::to_string(i));
    m.factors[i] = value(n, k, i);
    m.factor_std[i] = sd(n, k, i);
  }
  m.innovation_count = 5 + static_cast<std::uint64_t>(k);
  m.innovation_mean = -0.1 * k;
  m.nis_mean = 1.0 + k + 0.1 * static_cast<double>(n);
  m.last_innovation = 0.25 * k + static_cast<double>(n);
  m.last_innovation_variance = 1.0 + 0.5 * k;
  m.rejected_samples = 2 * static_cast<std::uint64_t>(k);
  return m;
}

void send_all(FactorSetAssembler& a, std::uint64_t n, std::vector<FactorSet>& out, const std::string& group = "ims2",
              causal_twin::TimeScale scale = causal_twin::CONDITION_LEVEL) {
  for (int k = 0; k < kG; ++k) a.add(message(n, k, group, scale), out);
}

// Every field of a set against the formulas; absent outcomes have no factors and default stats.
void expect_set(const FactorSet& s, std::uint64_t n, std::vector<bool> present = std::vector<bool>(kG, true)) {
  SCOPED_TRACE("set " + std::to_string(n));
  EXPECT_EQ(s.index, n);
  EXPECT_EQ(s.time_ns, kT0 + static_cast<std::int64_t>(n) * kStep);
  EXPECT_EQ(s.channel_count, kG);
  EXPECT_EQ(s.lag_order, 1);
  const bool complete = std::all_of(present.begin(), present.end(), [](bool p) { return p; });
  EXPECT_EQ(s.complete, complete);
  EXPECT_EQ(s.present, present);
  ASSERT_EQ(s.factor_offset.size(), static_cast<std::size_t>(kG + 1));
  std::vector<std::string> names;
  Eigen::Index at = 0;
  for (int k = 0; k < kG; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    EXPECT_EQ(s.factor_offset[ku], at);
    if (!present[ku]) {
      EXPECT_EQ(s.channel_names[ku], "");
      EXPECT_EQ(s.outcomes[ku].innovation_count, 0u);
      continue;
    }
    EXPECT_EQ(s.channel_names[ku], "b" + std::to_string(k + 1));
    for (int i = 0; i < factor_count(k); ++i) {
      names.push_back("x" + std::to_string(k + 1) + "_" + std::to_string(i));
      EXPECT_EQ(s.factors[at + i], value(n, k, i));
      EXPECT_EQ(s.factor_std[at + i], sd(n, k, i));
    }
    at += factor_count(k);
    const auto& o = s.outcomes[ku];
    EXPECT_EQ(o.innovation_count, 5u + static_cast<std::uint64_t>(k));
    EXPECT_EQ(o.innovation_mean, -0.1 * k);
    EXPECT_EQ(o.nis_mean, 1.0 + k + 0.1 * static_cast<double>(n));
    EXPECT_EQ(o.last_innovation, 0.25 * k + static_cast<double>(n));
    EXPECT_EQ(o.last_innovation_variance, 1.0 + 0.5 * k);
    EXPECT_EQ(o.rejected_samples, 2u * static_cast<std::uint64_t>(k));
  }
  EXPECT_EQ(s.factor_offset.back(), at);
  EXPECT_EQ(s.factors.size(), at);
  EXPECT_EQ(s.factor_names, names);
  if (complete) {
    ASSERT_EQ(s.covariance_blocks.size(), static_cast<std::size_t>(kG));
    for (int k = 0; k < kG; ++k) {
      EXPECT_TRUE(s.covariance_blocks[static_cast<std::size_t>(k)].isApprox(
          Eigen::MatrixXd::Identity(factor_count(k), factor_count(k)) * (1.0 + k)));
    }
  } else {
    EXPECT_TRUE(s.covariance_blocks.empty()) << "blocks are all or nothing";
  }
}

std::vector<std::uint64_t> indices(const std::vector<FactorSet>& sets) {
  std::vector<std::uint64_t> v;
  for (const auto& s : sets) v.push_back(s.index);
  return v;
}

std::vector<std::uint64_t> range(std::uint64_t first, std::uint64_t last) {
  std::vector<std::uint64_t> v;
  for (std::uint64_t n = first; n <= last; ++n) v.push_back(n);
  return v;
}

}  // namespace

TEST(FactorSetAssembler, OutOfOrderOutcomesOfOneIndexBecomeOneCompleteSet) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  std::mt19937_64 rng(4);
  for (std::uint64_t n = 0; n < 12; ++n) {
    std::vector<int> order{0, 1, 2};
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i = 0; i < order.size(); ++i) {
      EXPECT_EQ(a.add(message(n, order[i]), out), Status::Accepted);
      EXPECT_EQ(out.size(), i + 1 == order.size() ? n + 1 : n) << "complete only with all G outcomes";
    }
  }
  ASSERT_EQ(out.size(), 12u);
  for (std::uint64_t n = 0; n < 12; ++n) expect_set(out[n], n);
  const auto c = a.counters();
  EXPECT_EQ(c.accepted, 36u);
  EXPECT_EQ(c.complete, 12u);
  EXPECT_EQ(c.duplicates + c.refused + c.partial + c.dropped, 0u);
  EXPECT_EQ(a.pending(), 0u);
}

TEST(FactorSetAssembler, SeveralIndicesInAssemblyAtOnceComeOutInIndexOrder) {
  // Each outcome delivers in index order (one DDS instance), the outcomes run up to 4 indices apart.
  FactorSetAssembler a(8);
  std::vector<FactorSet> out;
  std::mt19937_64 rng(21);
  std::vector<std::uint64_t> next(kG, 0);
  std::uniform_int_distribution<int> pick(0, kG - 1);
  std::size_t sent = 0, most_pending = 0;
  while (sent < 40u * kG) {
    const int k = pick(rng);
    const auto ku = static_cast<std::size_t>(k);
    if (next[ku] >= 40 || next[ku] >= *std::min_element(next.begin(), next.end()) + 4) continue;
    EXPECT_EQ(a.add(message(next[ku]++, k), out), Status::Accepted);
    ++sent;
    most_pending = std::max(most_pending, a.pending());
  }
  EXPECT_GT(most_pending, 2u) << "the interleaving should keep several sets in assembly";
  EXPECT_EQ(indices(out), range(0, 39));
  for (const auto& s : out) expect_set(s, s.index);
  EXPECT_EQ(a.counters().complete, 40u);
}

TEST(FactorSetAssembler, ReSentIndicesAfterARestartAreDroppedAndCounted) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  for (std::uint64_t n = 0; n < 10; ++n) send_all(a, n, out);
  // The estimator restarts from its checkpoint at index 6: 6..9 again (other values: a new run of the
  // filter), then new indices.
  std::uint64_t sent = 10 * kG, duplicates = 0;
  for (std::uint64_t n = 6; n < 15; ++n) {
    for (int k = 0; k < kG; ++k) {
      FactorMessage m = message(n, k);
      if (n < 10) m.factors.array() += 1.0;
      const Status st = a.add(m, out);
      ++sent;
      EXPECT_EQ(st, n < 10 ? Status::Duplicate : Status::Accepted) << n;
      if (n < 10) ++duplicates;
    }
  }
  EXPECT_EQ(indices(out), range(0, 14)) << "each index exactly once";
  for (std::uint64_t n = 0; n < 15; ++n) expect_set(out[n], n);  // 6..9 keep their first values
  const auto c = a.counters();
  EXPECT_EQ(c.duplicates, duplicates);
  EXPECT_EQ(c.accepted + c.duplicates + c.refused, sent);
}

TEST(FactorSetAssembler, HistoricReplayToALateJoiningReaderIsDropped) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  for (std::uint64_t n = 0; n < 5; ++n) send_all(a, n, out);
  // The reader re-matches a transient-local writer: its history 0..4 comes again, outcome by outcome
  // (instance by instance), before the live indices 5 and 6.
  for (int k = 0; k < kG; ++k) {
    for (std::uint64_t n = 0; n < 5; ++n) EXPECT_EQ(a.add(message(n, k), out), Status::Duplicate);
  }
  send_all(a, 5, out);
  send_all(a, 6, out);
  EXPECT_EQ(indices(out), range(0, 6));
  EXPECT_EQ(a.counters().duplicates, 5u * kG);
  EXPECT_EQ(a.counters().complete, 7u);
}

TEST(FactorSetAssembler, SecondCopyOfAPendingOutcomeIsADuplicateAndTheFirstIsKept) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  a.add(message(3, 1), out);
  FactorMessage again = message(3, 1);
  again.factors.setConstant(9.0);
  EXPECT_EQ(a.add(again, out), Status::Duplicate);
  a.add(message(3, 0), out);
  a.add(message(3, 2), out);
  ASSERT_EQ(out.size(), 1u);
  expect_set(out[0], 3);
  EXPECT_EQ(a.counters().duplicates, 1u);
  EXPECT_EQ(a.counters().accepted, 3u);
}

TEST(FactorSetAssembler, MissingOutcomeIsDroppedOnceANewerSetCompletes) {
  FactorSetAssembler a(64, Policy::Drop);
  std::vector<FactorSet> out;
  send_all(a, 0, out);
  a.add(message(1, 0), out);
  a.add(message(1, 2), out);  // outcome 1 of index 1 is lost
  a.add(message(2, 1), out);
  a.add(message(2, 0), out);
  EXPECT_EQ(indices(out), range(0, 0));
  a.add(message(2, 2), out);  // every outcome is past index 1 now: it can never complete
  EXPECT_EQ(indices(out), (std::vector<std::uint64_t>{0, 2}));
  expect_set(out[1], 2);
  EXPECT_EQ(a.counters().dropped, 1u);
  EXPECT_EQ(a.pending(), 0u);
  // The lost message turns up after all: its index was given up, it is not emitted.
  EXPECT_EQ(a.add(message(1, 1), out), Status::Duplicate);
  EXPECT_EQ(out.size(), 2u);
  // A dropped index is one the consumer never got.
  const auto streams = a.streams();
  ASSERT_EQ(streams.size(), 1u);
  EXPECT_EQ(streams[0].missing, (std::vector<IndexRange>{{1, 1}}));
}

TEST(FactorSetAssembler, PendingSetsAreBoundedWhenAnOutcomeStopsArriving) {
  constexpr std::size_t kMax = 4;
  FactorSetAssembler a(kMax, Policy::Drop);
  std::vector<FactorSet> out;
  for (std::uint64_t n = 0; n < 10; ++n) {
    a.add(message(n, 0), out);
    a.add(message(n, 2), out);  // outcome 1 never comes
    EXPECT_LE(a.pending(), kMax);
  }
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(a.pending(), kMax);
  EXPECT_EQ(a.counters().dropped, 10u - kMax) << "the oldest are given up first";
  a.flush(out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(a.counters().dropped, 10u);
}

TEST(FactorSetAssembler, MissingOutcomeIsReleasedPartiallyUnderThePartialPolicy) {
  FactorSetAssembler a(64, Policy::ReleasePartial);
  std::vector<FactorSet> out;
  send_all(a, 0, out);
  a.add(message(1, 2), out);  // outcomes 0 and 1 of index 1 are lost
  send_all(a, 2, out);
  ASSERT_EQ(indices(out), range(0, 2)) << "index 1 goes out, partial, before the complete index 2";
  send_all(a, 3, out);
  ASSERT_EQ(indices(out), range(0, 3));
  expect_set(out[0], 0);
  expect_set(out[1], 1, {false, false, true});
  expect_set(out[2], 2);
  expect_set(out[3], 3);
  const auto c = a.counters();
  EXPECT_EQ(c.partial, 1u);
  EXPECT_EQ(c.complete, 3u);
  EXPECT_EQ(c.dropped, 0u);
}

TEST(FactorSetAssembler, FlushReleasesPendingSetsByThePolicyInIndexOrder) {
  for (Policy policy : {Policy::Drop, Policy::ReleasePartial}) {
    FactorSetAssembler a(16, policy);
    std::vector<FactorSet> out;
    send_all(a, 0, out);
    a.add(message(1, 0), out);
    a.add(message(2, 0), out);
    a.add(message(2, 1), out);
    a.add(message(3, 1), out);  // outcome 2 stopped after index 0
    EXPECT_EQ(indices(out), range(0, 0));
    a.flush(out);
    if (policy == Policy::Drop) {
      EXPECT_EQ(indices(out), range(0, 0));
      EXPECT_EQ(a.counters().dropped, 3u);
    } else {
      EXPECT_EQ(indices(out), range(0, 3));
      expect_set(out[1], 1, {true, false, false});
      expect_set(out[2], 2, {true, true, false});
      expect_set(out[3], 3, {false, true, false});
      EXPECT_EQ(a.counters().partial, 3u);
    }
    EXPECT_EQ(a.pending(), 0u);
    const std::size_t before = out.size();
    a.flush(out);
    EXPECT_EQ(out.size(), before) << "released once";
  }
}

TEST(FactorSetAssembler, TwoAssetGroupsInterleavedAreSeparateStreams) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  // The same indices from two groups, outcomes interleaved across the groups.
  for (std::uint64_t n = 0; n < 6; ++n) {
    for (int k = kG - 1; k >= 0; --k) {
      a.add(message(n, k, "shaft1"), out);
      a.add(message(n + 100, k, "shaft2"), out);
    }
  }
  ASSERT_EQ(out.size(), 12u);
  std::vector<std::uint64_t> one, two;
  for (const auto& s : out) {
    (s.stream.asset_group == "shaft1" ? one : two).push_back(s.index);
    expect_set(s, s.index);
  }
  EXPECT_EQ(one, range(0, 5));
  EXPECT_EQ(two, range(100, 105));
  // A re-sent index of one group is a duplicate there only.
  EXPECT_EQ(a.add(message(3, 0, "shaft1"), out), Status::Duplicate);
  EXPECT_EQ(a.add(message(3, 0, "shaft3"), out), Status::Accepted);
  EXPECT_EQ(a.streams().size(), 3u);
}

TEST(FactorSetAssembler, TimeScalesAndKindsAreSeparateStreamsAndOnlyConditionLevelTracksGaps) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  // Condition level: snapshots 0..3 and 7..8 (4..6 never sent). Sample level: every 1024th sample.
  for (std::uint64_t n : {0u, 1u, 2u, 3u, 7u, 8u}) send_all(a, n, out, "ims2", causal_twin::CONDITION_LEVEL);
  for (std::uint64_t n = 0; n < 4; ++n) send_all(a, 1023 + 1024 * n, out, "ims2", causal_twin::SAMPLE_LEVEL);
  // A smoother stream of the same group and index is a stream of its own.
  for (int k = 0; k < kG; ++k) {
    a.add(message(2, k, "ims2", causal_twin::CONDITION_LEVEL, causal_twin::FIXED_LAG_SMOOTHER), out);
  }
  ASSERT_EQ(out.size(), 11u);
  const auto streams = a.streams();
  ASSERT_EQ(streams.size(), 3u);
  for (const auto& r : streams) {
    SCOPED_TRACE(std::string(causal::dds::to_string(r.stream.time_scale)) + " " + causal::dds::to_string(r.stream.kind));
    if (r.stream.time_scale == causal_twin::SAMPLE_LEVEL) {
      EXPECT_FALSE(r.gaps_tracked);
      EXPECT_TRUE(r.missing.empty());
      EXPECT_EQ(r.counters.complete, 4u);
    } else if (r.stream.kind == causal_twin::FILTER) {
      EXPECT_TRUE(r.gaps_tracked);
      EXPECT_EQ(r.missing, (std::vector<IndexRange>{{4, 6}}));
      EXPECT_EQ(r.counters.complete, 6u);
    } else {
      EXPECT_EQ(r.counters.complete, 1u);
      EXPECT_TRUE(r.missing.empty());
    }
  }
}

TEST(FactorSetAssembler, InconsistentMessagesAreRefusedWithAReason) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  a.add(message(0, 0), out);
  FactorMessage wrong_g = message(0, 1);
  wrong_g.channel_count = 4;
  EXPECT_EQ(a.add(wrong_g, out), Status::Refused);
  EXPECT_NE(a.last_problem().find("channel count 4"), std::string::npos) << a.last_problem();
  FactorMessage bad_outcome = message(0, 1);
  bad_outcome.outcome = kG;
  EXPECT_EQ(a.add(bad_outcome, out), Status::Refused);
  FactorMessage ragged = message(0, 1);
  ragged.factor_std.resize(1);
  EXPECT_EQ(a.add(ragged, out), Status::Refused);
  FactorMessage nan = message(0, 1);
  nan.factors[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(a.add(nan, out), Status::Refused);
  EXPECT_NE(a.last_problem().find("non-finite"), std::string::npos);
  FactorMessage inf_sd = message(0, 1);
  inf_sd.factor_std[0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(a.add(inf_sd, out), Status::Refused);
  EXPECT_EQ(a.counters().refused, 5u);
  EXPECT_EQ(a.counters().accepted, 1u);
  // The set still completes with consistent messages.
  a.add(message(0, 1), out);
  a.add(message(0, 2), out);
  ASSERT_EQ(out.size(), 1u);
  expect_set(out[0], 0);
}

TEST(FactorSetAssembler, CovarianceBlocksAreAllOrNothing) {
  FactorSetAssembler a;
  std::vector<FactorSet> out;
  for (int k = 0; k < kG; ++k) {
    FactorMessage m = message(0, k);
    if (k == 1) m.covariance.resize(0, 0);  // e.g. a fixed-lag message carries none
    a.add(m, out);
  }
  // Index 1: outcome 2's block has the wrong shape, taken as none.
  for (int k = 0; k < kG; ++k) {
    FactorMessage m = message(1, k);
    if (k == 2) m.covariance = Eigen::MatrixXd::Identity(2, 3);
    EXPECT_EQ(a.add(m, out), Status::Accepted);
  }
  ASSERT_EQ(out.size(), 2u);
  for (const auto& s : out) {
    EXPECT_TRUE(s.complete);
    EXPECT_TRUE(s.covariance_blocks.empty());
  }
}
