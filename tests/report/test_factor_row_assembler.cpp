// Factor row assembly: G per-outcome messages of one index -> one CSV row (outcome-major), each index
// once, partial rows at exit, bounded pending rows, refusals, duplicates, gaps and layout changes.
#include "factor_row_assembler.hpp"

#include "causal/io/csv_format.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

using causal::dds::FactorMessage;
using causal::recorder::FactorRowAssembler;

namespace {

constexpr int kG = 3;
const std::int64_t kT0 = 1076581959LL * 1000000000LL;  // 2004-02-12 10:32:39 UTC
const std::int64_t kDt = 600LL * 1000000000LL;

// Names per the model convention, written out independently of SvarLayout: instantaneous x{k}{j}
// (j != k), then lag 1 xL{k}{j} including the self lag.
std::vector<std::string> names_of(int k) {
  std::vector<std::string> n;
  for (int j = 1; j <= kG; ++j) {
    if (j != k) n.push_back("x" + std::to_string(k) + std::to_string(j));
  }
  for (int j = 1; j <= kG; ++j) n.push_back("xL" + std::to_string(k) + std::to_string(j));
  return n;
}

double value_of(std::uint64_t n, int k, std::size_t i) { return 0.1 * k + 0.01 * static_cast<double>(i) + 1e-3 * static_cast<double>(n); }
double sd_of(std::uint64_t n, int k, std::size_t i) { return 0.05 + 1e-4 * (k + static_cast<double>(i)) + 1e-6 * static_cast<double>(n); }
double nis_of(std::uint64_t n, int k) { return 1.0 + 0.1 * k + 0.01 * static_cast<double>(n); }

// k is 1-based here; FactorMessage::outcome is 0-based.
FactorMessage message(std::uint64_t n, int k) {
  FactorMessage m;
  m.asset_group = "a";
  m.outcome = k - 1;
  m.channel_count = kG;
  m.lag_order = 1;
  m.sample_index = n;
  m.time_ns = kT0 + static_cast<std::int64_t>(n) * kDt;
  m.outcome_name = "Bearing " + std::to_string(k);
  m.factor_names = names_of(k);
  m.factors.resize(static_cast<Eigen::Index>(m.factor_names.size()));
  m.factor_std.resize(m.factors.size());
  for (std::size_t i = 0; i < m.factor_names.size(); ++i) {
    m.factors[static_cast<Eigen::Index>(i)] = value_of(n, k, i);
    m.factor_std[static_cast<Eigen::Index>(i)] = sd_of(n, k, i);
  }
  m.nis_mean = nis_of(n, k);
  return m;
}

std::vector<std::string> expected_header() {
  std::vector<std::string> h{"index", "time_ns", "time_utc"};
  for (int k = 1; k <= kG; ++k) for (const auto& n : names_of(k)) h.push_back(n);
  for (int k = 1; k <= kG; ++k) for (const auto& n : names_of(k)) h.push_back("sd_" + n);
  for (int k = 1; k <= kG; ++k) h.push_back("nis_Bearing " + std::to_string(k));
  return h;
}

double num(const std::string& s) {
  EXPECT_FALSE(s.empty());
  return std::strtod(s.c_str(), nullptr);
}

// Checks the cells of outcome k in a row against the generating formulas (or emptiness).
void check_outcome(const std::vector<std::string>& row, std::uint64_t n, int k, bool present) {
  const std::size_t per = names_of(1).size();
  const std::size_t f_total = per * kG;
  for (std::size_t i = 0; i < per; ++i) {
    const std::string& v = row[3 + (k - 1) * per + i];
    const std::string& s = row[3 + f_total + (k - 1) * per + i];
    if (present) {
      EXPECT_EQ(num(v), value_of(n, k, i)) << "index " << n << " outcome " << k << " factor " << i;
      EXPECT_EQ(num(s), sd_of(n, k, i));
    } else {
      EXPECT_EQ(v, "");
      EXPECT_EQ(s, "");
    }
  }
  const std::string& nis = row[3 + 2 * f_total + (k - 1)];
  if (present) EXPECT_EQ(num(nis), nis_of(n, k));
  else EXPECT_EQ(nis, "");
}

}  // namespace

TEST(FactorRowAssembler, RowIsWrittenOnlyWhenAllOutcomesArrived) {
  FactorRowAssembler a;
  EXPECT_EQ(a.add(message(0, 2)), FactorRowAssembler::AddStatus::Stored);
  EXPECT_EQ(a.add(message(0, 1)), FactorRowAssembler::AddStatus::Stored);
  EXPECT_FALSE(a.has_header());
  EXPECT_TRUE(a.take_rows().empty());
  EXPECT_EQ(a.add(message(0, 3)), FactorRowAssembler::AddStatus::Completed);
  ASSERT_TRUE(a.has_header());
  EXPECT_EQ(a.header(), expected_header());
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 1u);
  ASSERT_EQ(rows[0].size(), expected_header().size());
  EXPECT_EQ(rows[0][0], "0");
  EXPECT_EQ(rows[0][1], std::to_string(kT0));
  EXPECT_EQ(rows[0][2], "2004-02-12 10:32:39");
  for (int k = 1; k <= kG; ++k) check_outcome(rows[0], 0, k, true);
  EXPECT_EQ(a.pending(), 0u);
  EXPECT_EQ(a.counters().rows_complete, 1u);
}

TEST(FactorRowAssembler, InterleavedIndicesComeOutCompleteAndInOrder) {
  // Each outcome's own stream is in index order (one DDS instance), but the outcomes interleave freely.
  std::mt19937_64 rng(3);
  constexpr std::uint64_t kN = 40;
  std::vector<std::uint64_t> next(kG + 1, 0);
  FactorRowAssembler a;
  std::vector<std::vector<std::string>> rows;
  for (std::uint64_t sent = 0; sent < kN * kG;) {
    std::uniform_int_distribution<int> pick(1, kG);
    const int k = pick(rng);
    if (next[static_cast<std::size_t>(k)] >= kN) continue;
    a.add(message(next[static_cast<std::size_t>(k)]++, k));
    ++sent;
    for (auto& r : a.take_rows()) rows.push_back(std::move(r));
  }
  ASSERT_EQ(rows.size(), kN);
  for (std::uint64_t n = 0; n < kN; ++n) {
    EXPECT_EQ(rows[n][0], std::to_string(n));
    for (int k = 1; k <= kG; ++k) check_outcome(rows[n], n, k, true);
  }
  EXPECT_EQ(a.counters().messages, kN * kG);
  EXPECT_EQ(a.counters().rows_partial, 0u);
}

TEST(FactorRowAssembler, ExitWritesPartialRowsWithEmptyCells) {
  FactorRowAssembler a;
  for (int k = 1; k <= kG; ++k) a.add(message(0, k));
  a.add(message(1, 1));
  a.add(message(1, 3));
  a.add(message(2, 2));
  EXPECT_EQ(a.take_rows().size(), 1u);
  a.flush_pending();
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][0], "1");
  check_outcome(rows[0], 1, 1, true);
  check_outcome(rows[0], 1, 2, false);
  check_outcome(rows[0], 1, 3, true);
  EXPECT_EQ(rows[1][0], "2");
  check_outcome(rows[1], 2, 1, false);
  check_outcome(rows[1], 2, 2, true);
  check_outcome(rows[1], 2, 3, false);
  EXPECT_EQ(a.counters().rows_partial, 2u);
  EXPECT_EQ(a.pending(), 0u);
}

TEST(FactorRowAssembler, HeaderForcedBeforeEveryOutcomeWasSeenHasNisColumnsForAll) {
  FactorRowAssembler a;
  a.add(message(0, 1));
  a.add(message(0, 2));
  a.flush_pending();
  std::vector<std::string> h{"index", "time_ns", "time_utc"};
  for (int k = 1; k <= 2; ++k) for (const auto& n : names_of(k)) h.push_back(n);
  for (int k = 1; k <= 2; ++k) for (const auto& n : names_of(k)) h.push_back("sd_" + n);
  h.insert(h.end(), {"nis_Bearing 1", "nis_Bearing 2", "nis_y3"});
  EXPECT_EQ(a.header(), h);
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].back(), "");
  // Outcome 3 turns up later: its NIS has a column, its factors have none (counted, not misplaced).
  for (int k = 1; k <= kG; ++k) a.add(message(1, k));
  const auto later = a.take_rows();
  ASSERT_EQ(later.size(), 1u);
  EXPECT_EQ(num(later[0].back()), nis_of(1, 3));
  EXPECT_EQ(a.counters().dropped_factors, names_of(3).size());  // one per value (its sd goes with it)
}

TEST(FactorRowAssembler, PendingRowsAreBounded) {
  FactorRowAssembler a(4);
  for (std::uint64_t n = 0; n < 10; ++n) {
    a.add(message(n, 1));
    a.add(message(n, 2));  // outcome 3 never arrives
    EXPECT_LE(a.pending(), 4u);
  }
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 6u);
  // Outcome 3 was never seen: it has only its NIS column, empty; outcomes 1 and 2 are filled.
  const std::size_t per = names_of(1).size();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 3 + 2 * 2 * per + kG);
    EXPECT_EQ(rows[i][0], std::to_string(i));  // oldest first
    EXPECT_EQ(num(rows[i][3]), value_of(i, 1, 0));
    EXPECT_EQ(num(rows[i][3 + 2 * per + per + 1]), sd_of(i, 2, 1));  // sd block, outcome 2
    EXPECT_EQ(num(rows[i][3 + 4 * per + 1]), nis_of(i, 2));
    EXPECT_EQ(rows[i].back(), "");
  }
  EXPECT_EQ(a.counters().rows_partial, 6u);
}

TEST(FactorRowAssembler, RefusesInconsistentMessagesAndCountsDuplicates) {
  FactorRowAssembler a;
  a.add(message(0, 1));
  FactorMessage wrong_g = message(0, 2);
  wrong_g.channel_count = 4;
  EXPECT_EQ(a.add(wrong_g), FactorRowAssembler::AddStatus::Refused);
  FactorMessage bad_outcome = message(0, 2);
  bad_outcome.outcome = 3;
  EXPECT_EQ(a.add(bad_outcome), FactorRowAssembler::AddStatus::Refused);
  FactorMessage ragged = message(0, 2);
  ragged.factor_std.resize(2);
  EXPECT_EQ(a.add(ragged), FactorRowAssembler::AddStatus::Refused);
  EXPECT_EQ(a.counters().refused, 3u);

  FactorMessage nan = message(0, 2);
  nan.factors[0] = std::nan("");
  EXPECT_EQ(a.add(nan), FactorRowAssembler::AddStatus::Refused);
  EXPECT_NE(a.last_problem().find("non-finite"), std::string::npos) << a.last_problem();
  EXPECT_EQ(a.counters().refused, 4u);

  // A second copy of a pending outcome is a duplicate: the first copy stays (the old assembler let the
  // later copy replace it, so one row could mix two sends of an outcome).
  FactorMessage first = message(0, 2);
  first.nis_mean = 99.0;
  EXPECT_EQ(a.add(first), FactorRowAssembler::AddStatus::Stored);
  EXPECT_EQ(a.add(message(0, 2)), FactorRowAssembler::AddStatus::Duplicate);
  EXPECT_EQ(a.counters().duplicates, 1u);
  EXPECT_EQ(a.add(message(0, 3)), FactorRowAssembler::AddStatus::Completed);
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 1u);
  check_outcome(rows[0], 0, 1, true);
  check_outcome(rows[0], 0, 3, true);
  EXPECT_EQ(num(rows[0][3 + 2 * names_of(1).size() * kG + 1]), 99.0) << "outcome 2's NIS from the first copy";
  EXPECT_EQ(a.counters().messages, 3u);
}

TEST(FactorRowAssembler, ReSentAndReplayedIndicesAreWrittenOnce) {
  FactorRowAssembler a;
  std::uint64_t sent = 0;
  auto send = [&](std::uint64_t n, int k) {
    ++sent;
    return a.add(message(n, k));
  };
  for (std::uint64_t n = 0; n < 8; ++n) {
    for (int k = 1; k <= kG; ++k) send(n, k);
  }
  // Estimator restart from index 5, then a late-joining replay of 0..7 outcome by outcome, then new data.
  for (std::uint64_t n = 5; n < 8; ++n) {
    for (int k = 1; k <= kG; ++k) EXPECT_EQ(send(n, k), FactorRowAssembler::AddStatus::Duplicate);
  }
  for (int k = 1; k <= kG; ++k) {
    for (std::uint64_t n = 0; n < 8; ++n) EXPECT_EQ(send(n, k), FactorRowAssembler::AddStatus::Duplicate);
  }
  for (int k = kG; k >= 1; --k) send(8, k);  // outcomes out of order
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 9u);
  for (std::uint64_t n = 0; n < 9; ++n) {
    EXPECT_EQ(rows[n][0], std::to_string(n));
    for (int k = 1; k <= kG; ++k) check_outcome(rows[n], n, k, true);
  }
  const auto c = a.counters();
  EXPECT_EQ(c.duplicates, (3u + 8u) * kG);
  EXPECT_EQ(c.messages + c.duplicates + c.refused, sent) << "every message counted once";
  EXPECT_EQ(c.rows_complete, 9u);
}

TEST(FactorRowAssembler, ConditionLevelGapsAreReportedAsMissing) {
  FactorRowAssembler a;
  for (std::uint64_t n : {118u, 119u, 132u, 133u, 135u}) {
    for (int k = 1; k <= kG; ++k) {
      FactorMessage m = message(n, k);
      m.time_scale = causal_twin::CONDITION_LEVEL;
      a.add(m);
    }
  }
  EXPECT_EQ(a.take_rows().size(), 5u) << "rows are not held back for indices that never come";
  const auto streams = a.streams();
  ASSERT_EQ(streams.size(), 1u);
  EXPECT_TRUE(streams[0].gaps_tracked);
  EXPECT_EQ(streams[0].missing, (std::vector<causal::dds::IndexRange>{{120, 131}, {134, 134}}));
}

TEST(FactorRowAssembler, ChangedFactorOrderIsPlacedByName) {
  FactorRowAssembler a;
  for (int k = 1; k <= kG; ++k) a.add(message(0, k));
  a.take_rows();
  FactorMessage m = message(1, 1);
  std::reverse(m.factor_names.begin(), m.factor_names.end());
  m.factors.reverseInPlace();
  m.factor_std.reverseInPlace();
  m.factor_names.push_back("xL2_unknown");
  m.factors.conservativeResize(m.factors.size() + 1);
  m.factor_std.conservativeResize(m.factor_std.size() + 1);
  m.factors[m.factors.size() - 1] = 5.0;
  m.factor_std[m.factor_std.size() - 1] = 1.0;
  a.add(m);
  a.add(message(1, 2));
  a.add(message(1, 3));
  const auto rows = a.take_rows();
  ASSERT_EQ(rows.size(), 1u);
  for (int k = 1; k <= kG; ++k) check_outcome(rows[0], 1, k, true);
  EXPECT_EQ(a.counters().dropped_factors, 1u);
}
