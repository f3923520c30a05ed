// causal::dds factor conversions (common/dds/src/factor_conversions.cpp): FactorReports -> CausalFactorBatch
// (one batch per kind and index, every report in exactly one batch, 1-based outcomes in order, factor names
// from the layout) -> FactorMessage round trip through CDR, and batch validation; the packed lower-triangle
// covariance (pack/unpack, wire round trip, malformed counts).
#include "causal/dds/factor_conversions.hpp"

#include "causal_twinPubSubTypes.h"
#include "matrix_asserts.hpp"
#include "same_fields.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace causal::dds {
namespace {

using causal::pipeline::EstimateKind;
using causal::pipeline::FactorReport;

estimation::SvarLayout layout(int g, int m, bool self_lags = false) {
  estimation::ModelSpec s;
  s.channels = g;
  s.lag_order = m;
  s.include_self_lags = self_lags;
  return estimation::SvarLayout(s);
}

FactorReport report(const estimation::SvarLayout& l, int k, EstimateKind kind) {
  FactorReport r;
  r.kind = kind;
  r.outcome = k;
  r.sample_index = 123456789012ULL;
  r.time_ns = 1'077'000'000'123'456'789LL;
  const int d = l.factor_count(k);
  r.factors.resize(d);
  r.std_devs.resize(d);
  for (int i = 0; i < d; ++i) {
    r.factors[i] = 0.1 * (i + 1) - 0.35 + 1e-17 * i;
    r.std_devs[i] = 0.01 * (i + 2);
  }
  r.innovation_count = 1024;
  r.innovation_mean = -0.0123;
  r.nis_mean = 1.07;
  r.last_innovation = 0.5;
  r.last_innovation_variance = 0.25;
  r.rejected = 3;
  r.q = 1e-6;
  r.r = 1e-2;
  return r;
}

// A random SPD matrix A A^T + d I, made exactly symmetric (0.5 (P + P^T) is bitwise symmetric).
Eigen::MatrixXd random_spd(int d, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd a(d, d);
  for (int i = 0; i < d; ++i) {
    for (int j = 0; j < d; ++j) a(i, j) = normal(rng);
  }
  const Eigen::MatrixXd p = a * a.transpose() + d * Eigen::MatrixXd::Identity(d, d);
  return 0.5 * (p + p.transpose());
}

// Serialises and deserialises through the CDR wire format.
causal_twin::CausalFactorBatch through_the_wire(causal_twin::CausalFactorBatch m) {
  causal_twin::CausalFactorBatchPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&m)());
  EXPECT_TRUE(type.serialize(&m, &payload));
  causal_twin::CausalFactorBatch wire;
  EXPECT_TRUE(type.deserialize(&payload, &wire));
  return wire;
}

FactorContext context(const estimation::SvarLayout& l, const std::vector<std::string>& names) {
  FactorContext c;
  c.asset_group = "ims2";
  c.time_scale = causal_twin::CONDITION_LEVEL;
  c.feature = "rms";
  c.layout = &l;
  c.channel_names = names;
  return c;
}

// The batch of one report (one outcome block).
causal_twin::CausalFactorBatch batch_of(const FactorContext& c, const FactorReport& r) {
  const auto batches = causal::dds::to_causal_factor_batches(c, {r});
  EXPECT_EQ(batches.size(), 1u);
  EXPECT_EQ(batches.front().outcomes().size(), 1u);
  return batches.front();
}

TEST(FactorConversions, OutcomeIsOneBasedAndNamesFollowTheConvention) {
  const estimation::SvarLayout l = layout(4, 1);
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  const causal_twin::CausalFactorBatch b = batch_of(context(l, names), report(l, 2, EstimateKind::Filter));
  const causal_twin::OutcomeFactors& m = b.outcomes().front();
  EXPECT_EQ(m.outcome(), 3u);
  EXPECT_EQ(m.outcome_name(), "b3");
  EXPECT_EQ(b.channel_count(), 4u);
  EXPECT_EQ(b.lag_order(), 1u);
  EXPECT_EQ(b.kind(), causal_twin::FILTER);
  EXPECT_EQ(b.time_scale(), causal_twin::CONDITION_LEVEL);
  EXPECT_EQ(b.feature(), "rms");
  EXPECT_EQ(b.asset_group(), "ims2");
  // Outcome 3 of G=4, M=1 (see COMMON_RULES: instantaneous j ascending, then lag 1 j ascending).
  const std::vector<std::string> expected{"x31", "x32", "x34", "xL31", "xL32", "xL34"};
  EXPECT_EQ(m.factor_names(), expected);
  EXPECT_EQ(causal::dds::validate_causal_factor_batch(b), "");
}

TEST(FactorConversions, NamesForTenChannelsAndSecondLag) {
  const estimation::SvarLayout l = layout(10, 2, true);
  std::vector<std::string> names;
  for (int c = 1; c <= 10; ++c) names.push_back("ch" + std::to_string(c));
  const causal_twin::CausalFactorBatch b = batch_of(context(l, names), report(l, 9, EstimateKind::FixedLag));
  const causal_twin::OutcomeFactors& m = b.outcomes().front();
  EXPECT_EQ(m.outcome(), 10u);
  EXPECT_EQ(m.outcome_name(), "ch10");
  EXPECT_EQ(b.kind(), causal_twin::FIXED_LAG_SMOOTHER);
  EXPECT_EQ(b.lag_order(), 2u);
  // 9 instantaneous + 10 lag-1 (self included) + 10 lag-2.
  ASSERT_EQ(m.factor_names().size(), 29u);
  EXPECT_EQ(m.factor_names()[0], "x10_1");
  EXPECT_EQ(m.factor_names()[8], "x10_9");
  EXPECT_EQ(m.factor_names()[9], "xL10_1");
  EXPECT_EQ(m.factor_names()[18], "xL10_10");
  EXPECT_EQ(m.factor_names()[19], "xL2_10_1");
  EXPECT_EQ(m.factor_names()[28], "xL2_10_10");
}

// What a stream hands the estimator at one publication: every outcome's filter report at index n and the
// smoother's at n - L, outcomes in a scrambled order. Expected by hand: two batches (filter n, smoother n - L),
// in the order their first report came, each with outcomes 1..G once, in order, and every report's values.
TEST(FactorConversions, OneBatchPerKindAndIndexWithEveryOutcomeInOrder) {
  const estimation::SvarLayout l = layout(4, 1);
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  std::vector<FactorReport> reports;
  for (int k : {2, 0, 3, 1}) {
    FactorReport f = report(l, k, EstimateKind::Filter);
    f.sample_index = 2048;
    f.factors.setConstant(100.0 + k);
    reports.push_back(f);
    FactorReport s = report(l, 3 - k, EstimateKind::FixedLag);
    s.sample_index = 1024;
    s.time_ns = 77;
    s.factors.setConstant(200.0 + (3 - k));
    reports.push_back(s);
  }
  const auto batches = causal::dds::to_causal_factor_batches(context(l, names), reports);
  ASSERT_EQ(batches.size(), 2u);
  EXPECT_EQ(batches[0].kind(), causal_twin::FILTER);
  EXPECT_EQ(batches[0].sample_index(), 2048u);
  EXPECT_EQ(batches[1].kind(), causal_twin::FIXED_LAG_SMOOTHER);
  EXPECT_EQ(batches[1].sample_index(), 1024u);
  EXPECT_EQ(batches[1].time_ns(), 77);
  for (std::size_t b = 0; b < 2; ++b) {
    SCOPED_TRACE("batch " + std::to_string(b));
    ASSERT_EQ(batches[b].outcomes().size(), 4u);
    EXPECT_EQ(causal::dds::validate_causal_factor_batch(batches[b]), "");
    for (std::size_t k = 0; k < 4; ++k) {
      const auto& o = batches[b].outcomes()[k];
      EXPECT_EQ(o.outcome(), k + 1);
      EXPECT_EQ(o.outcome_name(), names[k]);
      ASSERT_EQ(o.factors().size(), 6u);
      EXPECT_EQ(o.factors()[0], (b == 0 ? 100.0 : 200.0) + static_cast<double>(k));
    }
  }
  EXPECT_TRUE(causal::dds::to_causal_factor_batches(context(l, names), {}).empty());
}

TEST(FactorConversions, RoundTripThroughTheBatchAndCdr) {
  const estimation::SvarLayout l = layout(4, 2, true);
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  for (EstimateKind kind : {EstimateKind::Filter, EstimateKind::FixedLag}) {
    std::vector<FactorReport> reports;
    for (int k = 0; k < 4; ++k) reports.push_back(report(l, k, kind));
    const auto batches = causal::dds::to_causal_factor_batches(context(l, names), reports);
    ASSERT_EQ(batches.size(), 1u);
    const causal_twin::CausalFactorBatch wire = through_the_wire(batches.front());
    ASSERT_EQ(causal::dds::validate_causal_factor_batch(wire), "");
    const std::vector<causal::dds::FactorMessage> back = causal::dds::from_causal_factor_batch(wire);
    ASSERT_EQ(back.size(), 4u);
    for (int k = 0; k < 4; ++k) {
      const FactorReport& r = reports[static_cast<std::size_t>(k)];
      const causal::dds::FactorMessage& m = back[static_cast<std::size_t>(k)];
      SCOPED_TRACE("outcome " + std::to_string(k));
      EXPECT_DOUBLE_EQ(wire.outcomes()[static_cast<std::size_t>(k)].process_noise_q(), 1e-6);
      EXPECT_DOUBLE_EQ(wire.outcomes()[static_cast<std::size_t>(k)].measurement_noise_r(), 1e-2);
      EXPECT_EQ(m.outcome, k);
      EXPECT_EQ(m.kind, kind == EstimateKind::Filter ? causal_twin::FILTER : causal_twin::FIXED_LAG_SMOOTHER);
      EXPECT_EQ(m.asset_group, "ims2");
      EXPECT_EQ(m.time_scale, causal_twin::CONDITION_LEVEL);
      EXPECT_EQ(m.feature, "rms");
      EXPECT_EQ(m.outcome_name, names[static_cast<std::size_t>(k)]);
      EXPECT_EQ(m.channel_count, 4);
      EXPECT_EQ(m.lag_order, 2);
      EXPECT_SAME_FIELDS(m, r, sample_index, time_ns);
      std::vector<std::string> layout_names;
      for (int i = 0; i < l.factor_count(k); ++i) layout_names.push_back(l.factor_name(k, i));
      EXPECT_EQ(m.factor_names, layout_names);
      EXPECT_TRUE((m.factors.array() == r.factors.array()).all());
      EXPECT_TRUE((m.factor_std.array() == r.std_devs.array()).all());
      EXPECT_SAME_FIELDS(m, r, innovation_count, innovation_mean, nis_mean, last_innovation, last_innovation_variance);
      EXPECT_EQ(m.rejected_samples, r.rejected);
    }
  }
}

TEST(FactorConversions, ValidateCatchesInconsistentBatches) {
  const estimation::SvarLayout l = layout(3, 1);
  std::vector<FactorReport> reports;
  for (int k = 0; k < 3; ++k) reports.push_back(report(l, k, EstimateKind::Filter));
  const auto good = causal::dds::to_causal_factor_batches(context(l, {"a", "b", "c"}), reports).front();
  ASSERT_EQ(causal::dds::validate_causal_factor_batch(good), "");
  const auto check = [](const causal_twin::CausalFactorBatch& m) { return causal::dds::validate_causal_factor_batch(m); };

  auto m = good;
  m.outcomes()[0].outcome(0);  // 1-based: 0 is invalid
  EXPECT_NE(check(m).find("outcome 0"), std::string::npos);
  m = good;
  m.outcomes()[2].outcome(4);
  EXPECT_NE(check(m).find("1..3"), std::string::npos);
  m = good;
  m.outcomes()[1].outcome(1);  // outcome 1 twice
  EXPECT_NE(check(m).find("not after outcome 1"), std::string::npos);
  m = good;
  std::swap(m.outcomes()[0], m.outcomes()[1]);  // out of order
  EXPECT_NE(check(m), "");
  m = good;
  m.outcomes().erase(m.outcomes().begin());  // a subset in order is consistent (the assemblers wait for the rest)
  EXPECT_EQ(check(m), "");
  m = good;
  m.outcomes().clear();
  EXPECT_NE(check(m).find("no outcome block"), std::string::npos);
  m = good;
  m.channel_count(1);
  m.outcomes().resize(1);
  EXPECT_NE(check(m), "");
  m = good;
  m.outcomes()[1].factors().push_back(1.0);
  EXPECT_NE(check(m).find("outcome 2"), std::string::npos);
  m = good;
  m.outcomes()[0].factor_std().pop_back();
  EXPECT_NE(check(m), "");
  m = good;
  m.outcomes()[2].factor_names().pop_back();
  EXPECT_NE(check(m), "");
}

TEST(FactorConversions, ToStringNames) {
  EXPECT_STREQ(causal::dds::to_string(causal_twin::FILTER), "filter");
  EXPECT_STREQ(causal::dds::to_string(causal_twin::FIXED_LAG_SMOOTHER), "fixed-lag");
  EXPECT_STREQ(causal::dds::to_string(causal_twin::RTS_SMOOTHER), "rts");
  EXPECT_STREQ(causal::dds::to_string(causal_twin::SAMPLE_LEVEL), "sample");
  EXPECT_STREQ(causal::dds::to_string(causal_twin::CONDITION_LEVEL), "condition");
}

// ---- covariance ------------------------------------------------------------------------------------------

TEST(FactorCovariance, PackIsTheLowerTriangleRowByRow) {
  // Independent truth written out by hand for d = 3 (documented order in the IDL).
  Eigen::MatrixXd p(3, 3);
  p << 11, 21, 31,
       21, 22, 32,
       31, 32, 33;
  p(0, 1) = -1.0;  // upper triangle is not read
  const std::vector<double> expected{11, 21, 22, 31, 32, 33};
  EXPECT_EQ(causal::dds::pack_lower_triangle(p), expected);
  EXPECT_TRUE(causal::dds::pack_lower_triangle(Eigen::MatrixXd(0, 0)).empty());
  EXPECT_THROW(causal::dds::pack_lower_triangle(Eigen::MatrixXd::Zero(2, 3)), std::invalid_argument);
}

TEST(FactorCovariance, PackUnpackRoundTripOfRandomSpdMatrices) {
  for (int d : {1, 3, 7}) {
    SCOPED_TRACE("d = " + std::to_string(d));
    const Eigen::MatrixXd p = random_spd(d, 100 + static_cast<std::uint64_t>(d));
    const std::vector<double> packed = causal::dds::pack_lower_triangle(p);
    ASSERT_EQ(packed.size(), static_cast<std::size_t>(d * (d + 1) / 2));
    const Eigen::MatrixXd back = causal::dds::unpack_lower_triangle(packed, d);
    ASSERT_EQ(back.rows(), d);
    ASSERT_EQ(back.cols(), d);
    EXPECT_TRUE((back.array() == p.array()).all()) << "bit-exact round trip";
    EXPECT_TRUE((back.array() == back.transpose().array()).all()) << "unpacked matrix must be symmetric";
    EXPECT_SPD(back, 0.0);
  }
}

TEST(FactorCovariance, UnpackWithTheWrongCountIsEmpty) {
  const std::vector<double> six{1, 2, 3, 4, 5, 6};  // d = 3
  EXPECT_EQ(causal::dds::unpack_lower_triangle(six, 3).rows(), 3);
  EXPECT_EQ(causal::dds::unpack_lower_triangle(six, 2).size(), 0);
  EXPECT_EQ(causal::dds::unpack_lower_triangle(six, 4).size(), 0);
  EXPECT_EQ(causal::dds::unpack_lower_triangle(std::vector<double>(5, 1.0), 3).size(), 0);
  EXPECT_EQ(causal::dds::unpack_lower_triangle(six, -1).size(), 0);
  EXPECT_EQ(causal::dds::unpack_lower_triangle({}, 0).size(), 0);
}

TEST(FactorCovariance, BatchRoundTripCarriesTheFullBlock) {
  const estimation::SvarLayout l = layout(4, 2, true);  // 3 + 4 + 4 = 11 factors per outcome
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  for (int k = 0; k < 4; ++k) {
    SCOPED_TRACE("outcome " + std::to_string(k));
    FactorReport r = report(l, k, EstimateKind::Filter);
    const int d = l.factor_count(k);
    r.covariance = random_spd(d, 7 + static_cast<std::uint64_t>(k));
    const causal_twin::CausalFactorBatch m = batch_of(context(l, names), r);
    const auto& block = m.outcomes().front().factor_covariance();
    ASSERT_EQ(block.size(), static_cast<std::size_t>(d * (d + 1) / 2));
    // Element (i, j), i >= j, sits at i(i+1)/2 + j: checked against the report directly.
    for (int i = 0; i < d; ++i) {
      for (int j = 0; j <= i; ++j) {
        ASSERT_EQ(block[static_cast<std::size_t>(i * (i + 1) / 2 + j)], r.covariance(i, j));
      }
    }
    const causal_twin::CausalFactorBatch wire = through_the_wire(m);
    ASSERT_EQ(causal::dds::validate_causal_factor_batch(wire), "");
    const causal::dds::FactorMessage back = causal::dds::from_causal_factor_batch(wire).front();
    ASSERT_EQ(back.covariance.rows(), d);
    ASSERT_EQ(back.covariance.cols(), d);
    EXPECT_TRUE((back.covariance.array() == r.covariance.array()).all());
  }
}

TEST(FactorCovariance, ReportsWithoutCovarianceSendAnEmptySequence) {
  const estimation::SvarLayout l = layout(3, 1);
  const std::vector<std::string> names{"a", "b", "c"};
  FactorReport fixed_lag = report(l, 1, EstimateKind::FixedLag);  // no covariance
  causal_twin::CausalFactorBatch m = batch_of(context(l, names), fixed_lag);
  EXPECT_TRUE(m.outcomes().front().factor_covariance().empty());
  EXPECT_EQ(causal::dds::validate_causal_factor_batch(m), "") << "empty covariance is valid";
  EXPECT_EQ(causal::dds::from_causal_factor_batch(through_the_wire(m)).front().covariance.size(), 0);
  // A block reused: a filter report with a covariance, then a fixed-lag one without.
  causal_twin::OutcomeFactors block;
  FactorReport filt = report(l, 1, EstimateKind::Filter);
  filt.covariance = random_spd(l.factor_count(1), 3);
  causal::dds::to_outcome_factors(context(l, names), filt, block);
  EXPECT_FALSE(block.factor_covariance().empty());
  causal::dds::to_outcome_factors(context(l, names), fixed_lag, block);
  EXPECT_TRUE(block.factor_covariance().empty()) << "no stale block from the previous report";
  // A block of the wrong size is not sent.
  filt.covariance = random_spd(l.factor_count(1) + 1, 4);
  causal::dds::to_outcome_factors(context(l, names), filt, block);
  EXPECT_TRUE(block.factor_covariance().empty());
}

TEST(FactorCovariance, WrongCountIsMalformedAndUnpacksEmpty) {
  const estimation::SvarLayout l = layout(3, 1);  // 4 factors per outcome: 10 values
  FactorReport r = report(l, 0, EstimateKind::Filter);
  r.covariance = random_spd(4, 11);
  const causal_twin::CausalFactorBatch good = batch_of(context(l, {"a", "b", "c"}), r);
  ASSERT_EQ(good.outcomes().front().factor_covariance().size(), 10u);
  ASSERT_EQ(causal::dds::validate_causal_factor_batch(good), "");
  for (std::size_t count : {1u, 4u, 9u, 11u, 16u}) {
    SCOPED_TRACE("count " + std::to_string(count));
    auto m = good;
    m.outcomes().front().factor_covariance().resize(count, 0.5);
    const auto wire = through_the_wire(m);
    EXPECT_NE(causal::dds::validate_causal_factor_batch(wire).find("factor_covariance"), std::string::npos);
    EXPECT_EQ(causal::dds::from_causal_factor_batch(wire).front().covariance.size(), 0) << "malformed block is dropped";
  }
}

}  // namespace

}  // namespace causal::dds
