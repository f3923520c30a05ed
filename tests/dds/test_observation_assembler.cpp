// causal::recommender::ObservationAssembler (services/alarm_recommender/observation_assembler.cpp): G per-outcome
// factor messages (the blocks of a CausalFactorBatch) of one index -> one Observation, whatever their arrival order, each index once and in
// index order (the collection itself is dds::FactorSetAssembler's, tested in test_factor_set_assembler.cpp);
// condition vectors joined by time; bounded waiting (max_pending) and bounded memory for indices that never
// complete.
#include "observation_assembler.hpp"
#include "factor_message_head.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace causal::recommender {
namespace {

using causal::dds::FactorMessage;

constexpr std::int64_t kT0 = 1'077'000'000'000'000'000LL;
constexpr std::int64_t kStep = 600'000'000'000LL;  // 10 min

estimation::SvarLayout make_layout(int g) {
  estimation::ModelSpec s;
  s.channels = g;
  s.lag_order = 1;
  s.include_self_lags = true;
  return estimation::SvarLayout(s);
}

double factor_value(std::uint64_t index, int global_factor) {
  return 0.001 * static_cast<double>(index) + 0.01 * global_factor - 0.2;
}

FactorMessage message(const estimation::SvarLayout& l, causal_twin::TimeScale scale, int k, std::uint64_t index,
                      causal_twin::EstimateKind kind = causal_twin::FILTER, const std::string& group = "ims2",
                      const std::string& feature = "rms") {
  const test::FactorStreamId id{group, scale, kind, scale == causal_twin::CONDITION_LEVEL ? feature : ""};
  FactorMessage m = test::factor_message_head(id, k, "b" + std::to_string(k + 1), l.channels(), l.lag_order(), index,
                                              kT0 + static_cast<std::int64_t>(index) * kStep);
  const int d = l.factor_count(k);
  m.factors.resize(d);
  m.factor_std.resize(d);
  for (int i = 0; i < d; ++i) {
    m.factor_names.push_back(l.factor_name(k, i));
    m.factors[i] = factor_value(index, l.offset(k) + i);
    m.factor_std[i] = 0.5 + 0.001 * (l.offset(k) + i);
  }
  m.innovation_count = 7;
  m.innovation_mean = 0.0;
  m.nis_mean = 1.0 + k + 0.1 * static_cast<double>(index);
  m.last_innovation = 0.25 * k - 0.3 + static_cast<double>(index);
  m.last_innovation_variance = 1.0 + 0.5 * k;
  return m;
}

Eigen::VectorXd condition_values(int g, std::uint64_t index) {
  Eigen::VectorXd v(g);
  for (int c = 0; c < g; ++c) v[c] = 0.06 + 0.001 * c + 1e-4 * static_cast<double>(index);
  return v;
}

// Checks everything that does not depend on features.
void expect_observation(const AssembledObservation& a, const estimation::SvarLayout& l, causal_twin::TimeScale scale,
                        std::uint64_t index) {
  SCOPED_TRACE("observation " + std::to_string(index));
  const int g = l.channels();
  EXPECT_EQ(a.asset_group, "ims2");
  EXPECT_EQ(a.time_scale, scale == causal_twin::SAMPLE_LEVEL ? advice::TimeScale::Sample : advice::TimeScale::Condition);
  EXPECT_EQ(a.lag_order, 1);
  EXPECT_EQ(a.factor_names, l.factor_names());
  ASSERT_EQ(a.channel_names.size(), static_cast<std::size_t>(g));
  for (int k = 0; k < g; ++k) EXPECT_EQ(a.channel_names[static_cast<std::size_t>(k)], "b" + std::to_string(k + 1));
  const auto& o = a.observation;
  EXPECT_EQ(o.index, index);
  EXPECT_EQ(o.time_ns, kT0 + static_cast<std::int64_t>(index) * kStep);
  ASSERT_EQ(o.factors.size(), l.total_factors());
  ASSERT_EQ(o.factor_std.size(), l.total_factors());
  for (int f = 0; f < l.total_factors(); ++f) {
    EXPECT_EQ(o.factors[f], factor_value(index, f)) << "factor " << f;
    EXPECT_EQ(o.factor_std[f], 0.5 + 0.001 * f);
  }
  ASSERT_EQ(o.innovations.size(), g);
  ASSERT_EQ(o.innovation_variances.size(), g);
  for (int k = 0; k < g; ++k) {
    EXPECT_EQ(o.innovations[k], 0.25 * k - 0.3 + static_cast<double>(index));
    EXPECT_EQ(o.innovation_variances[k], 1.0 + 0.5 * k);
  }
  if (scale == causal_twin::SAMPLE_LEVEL) {
    ASSERT_EQ(o.mean_nis.size(), g);
    for (int k = 0; k < g; ++k) EXPECT_EQ(o.mean_nis[k], 1.0 + k + 0.1 * static_cast<double>(index));
    EXPECT_EQ(o.features.size(), 0);
  }
}

TEST(ObservationAssembler, ShuffledOutcomesOfOneIndexBecomeOneObservation) {
  const estimation::SvarLayout l = make_layout(4);
  ObservationAssembler asm_(4);
  std::mt19937_64 rng(5);
  std::vector<AssembledObservation> out;
  for (std::uint64_t n = 0; n < 20; ++n) {
    std::vector<int> order{0, 1, 2, 3};
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i = 0; i < order.size(); ++i) {
      asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, order[i], n), out);
      EXPECT_EQ(out.size(), i + 1 == order.size() ? n + 1 : n) << "complete only with all G outcomes";
    }
  }
  ASSERT_EQ(out.size(), 20u);
  for (std::uint64_t n = 0; n < 20; ++n) expect_observation(out[n], l, causal_twin::SAMPLE_LEVEL, n);
  EXPECT_EQ(asm_.dropped_incomplete(), 0u);
}

TEST(ObservationAssembler, InterleavedIndicesAreAssembledSeparately) {
  const estimation::SvarLayout l = make_layout(3);
  ObservationAssembler asm_(4);
  std::mt19937_64 rng(9);
  // Each outcome is one DDS instance of one writer, so its messages come in index order; the outcomes
  // interleave freely, up to 5 indices apart: several indices are in assembly at once. (An order that
  // breaks per-instance order cannot occur: an index older than one already emitted is a duplicate.)
  std::vector<std::pair<int, std::uint64_t>> msgs;  // (outcome, index) for indices 0..29
  std::vector<std::uint64_t> next(3, 0);
  std::uniform_int_distribution<int> pick(0, 2);
  while (msgs.size() < 90) {
    const int k = pick(rng);
    const std::uint64_t lowest = *std::min_element(next.begin(), next.end());
    if (next[static_cast<std::size_t>(k)] >= 30 || next[static_cast<std::size_t>(k)] >= lowest + 5) continue;
    msgs.emplace_back(k, next[static_cast<std::size_t>(k)]++);
  }
  std::vector<AssembledObservation> out;
  for (const auto& [k, n] : msgs) asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, k, n), out);
  ASSERT_EQ(out.size(), 30u);
  std::map<std::uint64_t, const AssembledObservation*> by_index;
  for (const auto& a : out) by_index[a.observation.index] = &a;
  ASSERT_EQ(by_index.size(), 30u) << "each index exactly once";
  for (const auto& [n, a] : by_index) expect_observation(*a, l, causal_twin::SAMPLE_LEVEL, n);
  for (std::uint64_t n = 0; n < 30; ++n) EXPECT_EQ(out[n].observation.index, n) << "in index order";
}

TEST(ObservationAssembler, FixedLagMessagesAreIgnored) {
  const estimation::SvarLayout l = make_layout(3);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  for (int k = 0; k < 3; ++k) {
    asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, k, 0, causal_twin::FIXED_LAG_SMOOTHER), out);
    asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, 1, causal_twin::FIXED_LAG_SMOOTHER), out);
    asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, 2, causal_twin::RTS_SMOOTHER), out);
  }
  asm_.flush(out);
  EXPECT_TRUE(out.empty());
  // A fixed-lag message must not complete or corrupt a filter observation of the same index either.
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 0, 5), out);
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 1, 5, causal_twin::FIXED_LAG_SMOOTHER), out);
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 2, 5), out);
  EXPECT_TRUE(out.empty());
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 1, 5), out);
  ASSERT_EQ(out.size(), 1u);
  expect_observation(out[0], l, causal_twin::SAMPLE_LEVEL, 5);
}

TEST(ObservationAssembler, DuplicateOutcomeMessagesAreNotCountedTwice) {
  const estimation::SvarLayout l = make_layout(4);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  for (int k : {0, 0, 1, 2, 2}) asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, k, 3), out);
  EXPECT_TRUE(out.empty()) << "outcome 4 has not arrived";
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 3, 3), out);
  ASSERT_EQ(out.size(), 1u);
  expect_observation(out[0], l, causal_twin::SAMPLE_LEVEL, 3);
}

TEST(ObservationAssembler, NoUpdateSinceLastReportGivesNaNInnovations) {
  const estimation::SvarLayout l = make_layout(3);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  for (int k = 0; k < 3; ++k) {
    FactorMessage m = message(l, causal_twin::SAMPLE_LEVEL, k, 0);
    if (k == 1) m.innovation_count = 0;
    asm_.add_factors(m, out);
  }
  ASSERT_EQ(out.size(), 1u);
  const auto& o = out[0].observation;
  EXPECT_TRUE(std::isnan(o.innovations[1]));
  EXPECT_TRUE(std::isnan(o.innovation_variances[1]));
  EXPECT_TRUE(std::isnan(o.mean_nis[1]));
  EXPECT_FALSE(std::isnan(o.innovations[0]));
  EXPECT_FALSE(std::isnan(o.innovations[2]));
}

// Condition level: the condition-vector topic is not ordered with respect to the factor topic, so each vector
// may arrive up to an index before or after its observation's factor messages (which come from one writer,
// index by index, outcomes in any order). Every observation must get the vector of ITS time, in index order.
TEST(ObservationAssembler, ConditionVectorsJoinedByTimeRegardlessOfArrivalOrder) {
  const int g = 4;
  const estimation::SvarLayout l = make_layout(g);
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    ObservationAssembler asm_(4);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> shift(-1.0, 1.5);
    struct Event {
      double key;   // arrival order
      int outcome;  // -1: the condition vector
      std::uint64_t index;
    };
    std::vector<Event> events;
    for (std::uint64_t n = 0; n < 24; ++n) {
      std::vector<int> order{0, 1, 2, 3};
      std::shuffle(order.begin(), order.end(), rng);
      for (int i = 0; i < g; ++i) events.push_back({static_cast<double>(n) + 0.2 * i, order[static_cast<std::size_t>(i)], n});
      events.push_back({static_cast<double>(n) + shift(rng), -1, n});
    }
    std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.key < b.key; });
    std::vector<AssembledObservation> out;
    for (const Event& e : events) {
      if (e.outcome < 0) {
        asm_.add_condition("ims2", "rms", kT0 + static_cast<std::int64_t>(e.index) * kStep, condition_values(g, e.index),
                           out);
      } else {
        asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, e.outcome, e.index), out);
      }
    }
    EXPECT_EQ(out.size(), 24u) << "all joined before flush (seed " << seed << ")";
    asm_.flush(out);
    ASSERT_EQ(out.size(), 24u) << "seed " << seed;
    for (std::uint64_t n = 0; n < 24; ++n) {
      const auto& a = out[n];
      expect_observation(a, l, causal_twin::CONDITION_LEVEL, n);
      EXPECT_EQ(a.observation.mean_nis.size(), 0) << "condition level carries per-observation innovations only";
      ASSERT_EQ(a.observation.features.size(), g) << "observation " << n << " seed " << seed;
      EXPECT_TRUE((a.observation.features.array() == condition_values(g, n).array()).all()) << "observation " << n;
    }
  }
}

TEST(ObservationAssembler, ConditionVectorBeforeFactorsReleasesAtOnce) {
  const estimation::SvarLayout l = make_layout(2);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  asm_.add_condition("ims2", "rms", kT0, condition_values(2, 0), out);
  EXPECT_TRUE(out.empty());
  asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, 1, 0), out);
  EXPECT_TRUE(out.empty());
  asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, 0, 0), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].observation.features.size(), 2);
}

TEST(ObservationAssembler, ReleasedWithoutFeaturesAfterMaxPending) {
  const int g = 3;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(2);
  std::vector<AssembledObservation> out;
  auto complete = [&](std::uint64_t n) {
    for (int k = 0; k < g; ++k) asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, n), out);
  };
  complete(0);
  complete(1);
  EXPECT_TRUE(out.empty()) << "two observations may wait (max_pending = 2)";
  complete(2);
  ASSERT_EQ(out.size(), 1u) << "the third pushes the oldest out without features";
  EXPECT_EQ(out[0].observation.index, 0u);
  EXPECT_EQ(out[0].observation.features.size(), 0);
  // The vector of index 2 arrives: index 1 (older, no vector) still holds the queue in order.
  asm_.add_condition("ims2", "rms", kT0 + 2 * kStep, condition_values(g, 2), out);
  EXPECT_EQ(out.size(), 1u);
  // The vector of index 1 arrives: 1 and 2 both go, with their own features.
  asm_.add_condition("ims2", "rms", kT0 + 1 * kStep, condition_values(g, 1), out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[1].observation.index, 1u);
  EXPECT_EQ(out[2].observation.index, 2u);
  EXPECT_TRUE((out[1].observation.features.array() == condition_values(g, 1).array()).all());
  EXPECT_TRUE((out[2].observation.features.array() == condition_values(g, 2).array()).all());
  // A late vector for the already released index 0 changes nothing.
  asm_.add_condition("ims2", "rms", kT0, condition_values(g, 0), out);
  asm_.flush(out);
  EXPECT_EQ(out.size(), 3u);
}

TEST(ObservationAssembler, FlushReleasesEverythingHeld) {
  const int g = 2;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(10);
  std::vector<AssembledObservation> out;
  for (std::uint64_t n = 0; n < 5; ++n) {
    for (int k = 0; k < g; ++k) asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, n), out);
  }
  EXPECT_TRUE(out.empty());
  asm_.flush(out);
  ASSERT_EQ(out.size(), 5u);
  for (std::uint64_t n = 0; n < 5; ++n) {
    EXPECT_EQ(out[n].observation.index, n);
    EXPECT_EQ(out[n].observation.features.size(), 0);
  }
  out.clear();
  asm_.flush(out);
  EXPECT_TRUE(out.empty()) << "flushed observations are released once";
}

TEST(ObservationAssembler, VectorsOfAnotherFeatureOrGroupAreNotJoined) {
  const int g = 2;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  asm_.add_condition("ims2", "kurtosis", kT0, condition_values(g, 0), out);
  asm_.add_condition("other", "rms", kT0, condition_values(g, 0), out);
  for (int k = 0; k < g; ++k) asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, 0), out);
  EXPECT_TRUE(out.empty());
  asm_.flush(out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].observation.features.size(), 0);
}

TEST(ObservationAssembler, GroupsAndTimeScalesAreSeparateStreams) {
  const int g = 2;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  // Same index on the sample level, the condition level and another group: three observations.
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 0, 0), out);
  asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, 1, 0), out);
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 1, 0, causal_twin::FILTER, "other"), out);
  EXPECT_TRUE(out.empty());
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 1, 0), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].asset_group, "ims2");
  EXPECT_EQ(out[0].time_scale, advice::TimeScale::Sample);
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 0, 0, causal_twin::FILTER, "other"), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].asset_group, "other");
  asm_.add_condition("ims2", "rms", kT0, condition_values(g, 0), out);
  asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, 0, 0), out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[2].time_scale, advice::TimeScale::Condition);
  EXPECT_EQ(out[2].observation.features.size(), g);
}

TEST(ObservationAssembler, LostOutcomeMessagesDoNotPinMemory) {
  const int g = 3;
  const estimation::SvarLayout l = make_layout(g);
  constexpr std::size_t kMaxSets = 8;
  ObservationAssembler asm_(4, kMaxSets);
  std::vector<AssembledObservation> out;
  const std::uint64_t lost = 1000;
  for (std::uint64_t n = 0; n < lost; ++n) {
    // Outcome 2 of every index is lost on the way.
    asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 0, n), out);
    asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 1, n), out);
  }
  EXPECT_TRUE(out.empty());
  // Incomplete indices are given up (bounded state): exactly kMaxSets of them are still held.
  EXPECT_EQ(asm_.dropped_incomplete(), lost - kMaxSets);
  // The stream still works afterwards: a complete index comes out at once, the held ones are given up
  // (every outcome is past them, they can never complete).
  for (int k = 0; k < g; ++k) asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, k, lost + 5), out);
  ASSERT_EQ(out.size(), 1u);
  expect_observation(out[0], l, causal_twin::SAMPLE_LEVEL, lost + 5);
  EXPECT_EQ(asm_.dropped_incomplete(), lost);
  // The lost message of an index that was given up turns up late: a duplicate, never a second observation
  // behind a newer one (the old assembler emitted it, out of order).
  asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, 2, lost - 1), out);
  asm_.flush(out);
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(asm_.factor_counters().duplicates, 1u);
}

TEST(ObservationAssembler, ReSentAndReplayedIndicesGiveNoSecondObservation) {
  const int g = 3;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  auto send = [&](std::uint64_t n) {
    for (int k = 0; k < g; ++k) asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, k, n), out);
  };
  for (std::uint64_t n = 0; n < 10; ++n) send(n);
  for (std::uint64_t n = 7; n < 12; ++n) send(n);  // estimator restarted from index 7
  for (std::uint64_t n = 0; n < 12; ++n) send(n);  // a transient-local history replayed
  send(12);
  ASSERT_EQ(out.size(), 13u) << "each index exactly once";
  for (std::uint64_t n = 0; n < 13; ++n) expect_observation(out[n], l, causal_twin::SAMPLE_LEVEL, n);
  const auto c = asm_.factor_counters();
  EXPECT_EQ(c.duplicates, (3u + 12u) * g);
  EXPECT_EQ(c.accepted, 13u * g);
  EXPECT_EQ(c.accepted + c.duplicates + c.refused, (10u + 5u + 12u + 1u) * g) << "sent == counted";
}

TEST(ObservationAssembler, ObservationIndexIsTheSnapshotIndexNotACount) {
  const int g = 2;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  // A consumer that joins late sees snapshots 533, 534 and (after a gap in the source) 540.
  for (std::uint64_t n : {533u, 534u, 540u}) {
    asm_.add_condition("ims2", "rms", kT0 + static_cast<std::int64_t>(n) * kStep, condition_values(g, n), out);
    for (int k = 0; k < g; ++k) asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, n), out);
  }
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].observation.index, 533u);
  EXPECT_EQ(out[1].observation.index, 534u);
  EXPECT_EQ(out[2].observation.index, 540u);
  for (const auto& a : out) expect_observation(a, l, causal_twin::CONDITION_LEVEL, a.observation.index);
}

TEST(ObservationAssembler, TwoAssetGroupsInterleavedOnBothTimeScales) {
  const int g = 2;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  std::map<std::pair<std::string, int>, std::vector<std::uint64_t>> seen;
  for (std::uint64_t n = 0; n < 6; ++n) {
    for (const std::string group : {"ims2", "other"}) {
      asm_.add_condition(group, "rms", kT0 + static_cast<std::int64_t>(n) * kStep, condition_values(g, n), out);
    }
    // Outcomes of both groups and both scales interleaved, outcome 2 first.
    for (int k = g - 1; k >= 0; --k) {
      for (const std::string group : {"ims2", "other"}) {
        asm_.add_factors(message(l, causal_twin::CONDITION_LEVEL, k, n, causal_twin::FILTER, group), out);
        asm_.add_factors(message(l, causal_twin::SAMPLE_LEVEL, k, 1024 * n, causal_twin::FILTER, group), out);
      }
    }
  }
  asm_.flush(out);
  ASSERT_EQ(out.size(), 24u);
  for (const auto& a : out) {
    seen[{a.asset_group, static_cast<int>(a.time_scale)}].push_back(a.observation.index);
    if (a.time_scale == advice::TimeScale::Condition) {
      EXPECT_TRUE((a.observation.features.array() == condition_values(g, a.observation.index).array()).all());
    }
  }
  for (const std::string group : {"ims2", "other"}) {
    EXPECT_EQ(seen[std::make_pair(group, static_cast<int>(causal_twin::CONDITION_LEVEL))], (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(seen[std::make_pair(group, static_cast<int>(causal_twin::SAMPLE_LEVEL))], (std::vector<std::uint64_t>{0, 1024, 2048, 3072, 4096, 5120}));
  }
  EXPECT_EQ(asm_.factor_counters().complete, 24u);
}

// Per-outcome covariance blocks: a distinct, recognisable SPD block per (outcome, index).
Eigen::MatrixXd block(int d, int k, std::uint64_t index) {
  Eigen::MatrixXd p(d, d);
  for (int i = 0; i < d; ++i) {
    for (int j = 0; j < d; ++j) p(i, j) = (i == j ? 1.0 + k : 0.3) + 0.001 * static_cast<double>(index) * (i + j);
  }
  return p;
}

TEST(ObservationAssembler, CovarianceBlocksReachTheObservationInOutcomeOrder) {
  const int g = 4;
  const estimation::SvarLayout l = make_layout(g);
  for (causal_twin::TimeScale scale : {causal_twin::SAMPLE_LEVEL, causal_twin::CONDITION_LEVEL}) {
    ObservationAssembler asm_(4);
    std::vector<AssembledObservation> out;
    for (int k : {2, 0, 3, 1}) {  // arrival order differs from outcome order
      FactorMessage m = message(l, scale, k, 8);
      m.covariance = block(l.factor_count(k), k, 8);
      asm_.add_factors(m, out);
    }
    asm_.flush(out);
    ASSERT_EQ(out.size(), 1u);
    const auto& blocks = out[0].covariance_blocks;
    ASSERT_EQ(blocks.size(), static_cast<std::size_t>(g));
    for (int k = 0; k < g; ++k) {
      const Eigen::MatrixXd want = block(l.factor_count(k), k, 8);
      const auto& got = blocks[static_cast<std::size_t>(k)];
      ASSERT_EQ(got.rows(), want.rows()) << "outcome " << k;
      ASSERT_EQ(got.cols(), want.cols()) << "outcome " << k;
      EXPECT_TRUE((got.array() == want.array()).all()) << "outcome " << k;
    }
    expect_observation(out[0], l, scale, 8);
  }
}

TEST(ObservationAssembler, CovarianceBlocksAreAllOrNothing) {
  const int g = 3;
  const estimation::SvarLayout l = make_layout(g);
  ObservationAssembler asm_(4);
  std::vector<AssembledObservation> out;
  // Index 0: outcome 1 without a block. Index 1: outcome 2 with a block of the wrong size.
  // Index 2: no blocks at all. Index 3: all blocks.
  for (std::uint64_t n = 0; n < 4; ++n) {
    for (int k = 0; k < g; ++k) {
      FactorMessage m = message(l, causal_twin::SAMPLE_LEVEL, k, n);
      const int d = l.factor_count(k);
      if (n == 0 && k != 1) m.covariance = block(d, k, n);
      if (n == 1) m.covariance = block(k == 2 ? d - 1 : d, k, n);
      if (n == 3) m.covariance = block(d, k, n);
      asm_.add_factors(m, out);
    }
  }
  ASSERT_EQ(out.size(), 4u);
  EXPECT_TRUE(out[0].covariance_blocks.empty()) << "one outcome without a block";
  EXPECT_TRUE(out[1].covariance_blocks.empty()) << "one block of the wrong size";
  EXPECT_TRUE(out[2].covariance_blocks.empty()) << "no blocks";
  EXPECT_EQ(out[3].covariance_blocks.size(), static_cast<std::size_t>(g));
}

}  // namespace

}  // namespace causal::recommender
