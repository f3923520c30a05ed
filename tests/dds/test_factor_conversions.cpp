// causal::dds factor conversions (common/dds/src/factor_conversions.cpp): FactorReport -> CausalFactors
// (1-based outcome, factor names from the layout) -> FactorMessage round trip, and message validation;
// the packed lower-triangle covariance (pack/unpack, wire round trip, malformed counts).
#include "causal/dds/factor_conversions.hpp"

#include "causal_twinPubSubTypes.h"
#include "matrix_asserts.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using causal::ModelSpec;
using causal::SvarLayout;
using causal::dds::FactorContext;
using causal::pipeline::EstimateKind;
using causal::pipeline::FactorReport;

SvarLayout layout(int g, int m, bool self_lags = false) {
  ModelSpec s;
  s.channels = g;
  s.lag_order = m;
  s.include_self_lags = self_lags;
  return SvarLayout(s);
}

FactorReport report(const SvarLayout& l, int k, EstimateKind kind) {
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
causal_twin::CausalFactors through_the_wire(causal_twin::CausalFactors m) {
  causal_twin::CausalFactorsPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&m)());
  EXPECT_TRUE(type.serialize(&m, &payload));
  causal_twin::CausalFactors wire;
  EXPECT_TRUE(type.deserialize(&payload, &wire));
  return wire;
}

FactorContext context(const SvarLayout& l, const std::vector<std::string>& names) {
  FactorContext c;
  c.asset_group = "ims2";
  c.time_scale = causal_twin::CONDITION_LEVEL;
  c.feature = "rms";
  c.layout = &l;
  c.channel_names = names;
  return c;
}

TEST(FactorConversions, OutcomeIsOneBasedAndNamesFollowTheConvention) {
  const SvarLayout l = layout(4, 1);
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  causal_twin::CausalFactors m;
  causal::dds::to_causal_factors(context(l, names), report(l, 2, EstimateKind::Filter), m);
  EXPECT_EQ(m.outcome(), 3u);
  EXPECT_EQ(m.outcome_name(), "b3");
  EXPECT_EQ(m.channel_count(), 4u);
  EXPECT_EQ(m.lag_order(), 1u);
  EXPECT_EQ(m.kind(), causal_twin::FILTER);
  EXPECT_EQ(m.time_scale(), causal_twin::CONDITION_LEVEL);
  EXPECT_EQ(m.feature(), "rms");
  EXPECT_EQ(m.asset_group(), "ims2");
  // Outcome 3 of G=4, M=1 (see COMMON_RULES: instantaneous j ascending, then lag 1 j ascending).
  const std::vector<std::string> expected{"x31", "x32", "x34", "xL31", "xL32", "xL34"};
  EXPECT_EQ(m.factor_names(), expected);
  EXPECT_EQ(causal::dds::validate_causal_factors(m), "");
}

TEST(FactorConversions, NamesForTenChannelsAndSecondLag) {
  const SvarLayout l = layout(10, 2, true);
  std::vector<std::string> names;
  for (int c = 1; c <= 10; ++c) names.push_back("ch" + std::to_string(c));
  causal_twin::CausalFactors m;
  causal::dds::to_causal_factors(context(l, names), report(l, 9, EstimateKind::FixedLag), m);
  EXPECT_EQ(m.outcome(), 10u);
  EXPECT_EQ(m.outcome_name(), "ch10");
  EXPECT_EQ(m.kind(), causal_twin::FIXED_LAG_SMOOTHER);
  EXPECT_EQ(m.lag_order(), 2u);
  // 9 instantaneous + 10 lag-1 (self included) + 10 lag-2.
  ASSERT_EQ(m.factor_names().size(), 29u);
  EXPECT_EQ(m.factor_names()[0], "x10_1");
  EXPECT_EQ(m.factor_names()[8], "x10_9");
  EXPECT_EQ(m.factor_names()[9], "xL10_1");
  EXPECT_EQ(m.factor_names()[18], "xL10_10");
  EXPECT_EQ(m.factor_names()[19], "xL2_10_1");
  EXPECT_EQ(m.factor_names()[28], "xL2_10_10");
}

TEST(FactorConversions, RoundTripThroughTheMessageAndCdr) {
  const SvarLayout l = layout(4, 2, true);
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  for (int k = 0; k < 4; ++k) {
    for (EstimateKind kind : {EstimateKind::Filter, EstimateKind::FixedLag}) {
      const FactorReport r = report(l, k, kind);
      causal_twin::CausalFactors m;
      causal::dds::to_causal_factors(context(l, names), r, m);
      // Through the wire format too.
      causal_twin::CausalFactorsPubSubType type;
      eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&m)());
      ASSERT_TRUE(type.serialize(&m, &payload));
      causal_twin::CausalFactors wire;
      ASSERT_TRUE(type.deserialize(&payload, &wire));
      ASSERT_EQ(causal::dds::validate_causal_factors(wire), "");
      EXPECT_DOUBLE_EQ(wire.process_noise_q(), 1e-6);
      EXPECT_DOUBLE_EQ(wire.measurement_noise_r(), 1e-2);

      const causal::dds::FactorMessage back = causal::dds::from_causal_factors(wire);
      SCOPED_TRACE("outcome " + std::to_string(k));
      EXPECT_EQ(back.outcome, k);
      EXPECT_EQ(back.kind, kind == EstimateKind::Filter ? causal_twin::FILTER : causal_twin::FIXED_LAG_SMOOTHER);
      EXPECT_EQ(back.asset_group, "ims2");
      EXPECT_EQ(back.time_scale, causal_twin::CONDITION_LEVEL);
      EXPECT_EQ(back.feature, "rms");
      EXPECT_EQ(back.outcome_name, names[static_cast<std::size_t>(k)]);
      EXPECT_EQ(back.channel_count, 4);
      EXPECT_EQ(back.lag_order, 2);
      EXPECT_EQ(back.sample_index, r.sample_index);
      EXPECT_EQ(back.time_ns, r.time_ns);
      std::vector<std::string> layout_names;
      for (int i = 0; i < l.factor_count(k); ++i) layout_names.push_back(l.factor_name(k, i));
      EXPECT_EQ(back.factor_names, layout_names);
      EXPECT_TRUE((back.factors.array() == r.factors.array()).all());
      EXPECT_TRUE((back.factor_std.array() == r.std_devs.array()).all());
      EXPECT_EQ(back.innovation_count, r.innovation_count);
      EXPECT_EQ(back.innovation_mean, r.innovation_mean);
      EXPECT_EQ(back.nis_mean, r.nis_mean);
      EXPECT_EQ(back.last_innovation, r.last_innovation);
      EXPECT_EQ(back.last_innovation_variance, r.last_innovation_variance);
      EXPECT_EQ(back.rejected_samples, r.rejected);
    }
  }
}

TEST(FactorConversions, ValidateCatchesInconsistentMessages) {
  const SvarLayout l = layout(3, 1);
  causal_twin::CausalFactors good;
  causal::dds::to_causal_factors(context(l, {"a", "b", "c"}), report(l, 0, EstimateKind::Filter), good);
  ASSERT_EQ(causal::dds::validate_causal_factors(good), "");

  auto m = good;
  m.outcome(0);  // 1-based: 0 is invalid
  EXPECT_NE(causal::dds::validate_causal_factors(m).find("outcome 0"), std::string::npos);
  m = good;
  m.outcome(4);
  EXPECT_NE(causal::dds::validate_causal_factors(m).find("1..3"), std::string::npos);
  m = good;
  m.outcome(3);
  EXPECT_EQ(causal::dds::validate_causal_factors(m), "") << "G itself is a valid 1-based outcome";
  m = good;
  m.channel_count(1);
  m.outcome(1);
  EXPECT_NE(causal::dds::validate_causal_factors(m), "");
  m = good;
  m.factors().push_back(1.0);
  EXPECT_NE(causal::dds::validate_causal_factors(m), "");
  m = good;
  m.factor_std().pop_back();
  EXPECT_NE(causal::dds::validate_causal_factors(m), "");
  m = good;
  m.factor_names().pop_back();
  EXPECT_NE(causal::dds::validate_causal_factors(m), "");
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

TEST(FactorCovariance, MessageRoundTripCarriesTheFullBlock) {
  const SvarLayout l = layout(4, 2, true);  // 3 + 4 + 4 = 11 factors per outcome
  const std::vector<std::string> names{"b1", "b2", "b3", "b4"};
  for (int k = 0; k < 4; ++k) {
    SCOPED_TRACE("outcome " + std::to_string(k));
    FactorReport r = report(l, k, EstimateKind::Filter);
    const int d = l.factor_count(k);
    r.covariance = random_spd(d, 7 + static_cast<std::uint64_t>(k));
    causal_twin::CausalFactors m;
    causal::dds::to_causal_factors(context(l, names), r, m);
    ASSERT_EQ(m.factor_covariance().size(), static_cast<std::size_t>(d * (d + 1) / 2));
    // Element (i, j), i >= j, sits at i(i+1)/2 + j: checked against the report directly.
    for (int i = 0; i < d; ++i) {
      for (int j = 0; j <= i; ++j) {
        ASSERT_EQ(m.factor_covariance()[static_cast<std::size_t>(i * (i + 1) / 2 + j)], r.covariance(i, j));
      }
    }
    const causal_twin::CausalFactors wire = through_the_wire(m);
    ASSERT_EQ(causal::dds::validate_causal_factors(wire), "");
    const causal::dds::FactorMessage back = causal::dds::from_causal_factors(wire);
    ASSERT_EQ(back.covariance.rows(), d);
    ASSERT_EQ(back.covariance.cols(), d);
    EXPECT_TRUE((back.covariance.array() == r.covariance.array()).all());
  }
}

TEST(FactorCovariance, ReportsWithoutCovarianceSendAnEmptySequence) {
  const SvarLayout l = layout(3, 1);
  const std::vector<std::string> names{"a", "b", "c"};
  FactorReport fixed_lag = report(l, 1, EstimateKind::FixedLag);  // no covariance
  causal_twin::CausalFactors m;
  causal::dds::to_causal_factors(context(l, names), fixed_lag, m);
  EXPECT_TRUE(m.factor_covariance().empty());
  EXPECT_EQ(causal::dds::validate_causal_factors(m), "") << "empty covariance is valid";
  EXPECT_EQ(causal::dds::from_causal_factors(through_the_wire(m)).covariance.size(), 0);
  // A writer reusing its message: a filter report with a block, then a fixed-lag one without.
  FactorReport filt = report(l, 1, EstimateKind::Filter);
  filt.covariance = random_spd(l.factor_count(1), 3);
  causal::dds::to_causal_factors(context(l, names), filt, m);
  EXPECT_FALSE(m.factor_covariance().empty());
  causal::dds::to_causal_factors(context(l, names), fixed_lag, m);
  EXPECT_TRUE(m.factor_covariance().empty()) << "no stale block from the previous report";
  // A block of the wrong size is not sent.
  filt.covariance = random_spd(l.factor_count(1) + 1, 4);
  causal::dds::to_causal_factors(context(l, names), filt, m);
  EXPECT_TRUE(m.factor_covariance().empty());
}

TEST(FactorCovariance, WrongCountIsMalformedAndUnpacksEmpty) {
  const SvarLayout l = layout(3, 1);  // 4 factors per outcome: 10 values
  FactorReport r = report(l, 0, EstimateKind::Filter);
  r.covariance = random_spd(4, 11);
  causal_twin::CausalFactors good;
  causal::dds::to_causal_factors(context(l, {"a", "b", "c"}), r, good);
  ASSERT_EQ(good.factor_covariance().size(), 10u);
  ASSERT_EQ(causal::dds::validate_causal_factors(good), "");
  for (std::size_t count : {1u, 4u, 9u, 11u, 16u}) {
    SCOPED_TRACE("count " + std::to_string(count));
    auto m = good;
    m.factor_covariance().resize(count, 0.5);
    const auto wire = through_the_wire(m);
    EXPECT_NE(causal::dds::validate_causal_factors(wire).find("factor_covariance"), std::string::npos);
    EXPECT_EQ(causal::dds::from_causal_factors(wire).covariance.size(), 0) << "malformed block is dropped";
  }
}

}  // namespace
