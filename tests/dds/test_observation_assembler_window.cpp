// causal::recommender::ObservationAssembler with the estimator's calibration replay: the estimator holds a
// structure window of condition vectors and sends their factors only once it has learned on them, so the
// recommender receives hundreds of condition vectors before the first factors. Every one of them must still
// be joined with its observation (the first observations are the alarm engine's baseline), and what was
// joined is not kept.
#include "observation_assembler.hpp"
#include "factor_message_head.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace causal::recommender {
namespace {

constexpr std::int64_t kT0 = 1'077'000'000'000'000'000LL;
constexpr std::int64_t kStep = 600'000'000'000LL;  // 10 min

dds::FactorMessage message(const estimation::SvarLayout& l, int k, std::uint64_t index) {
  const test::FactorStreamId id{"wide", causal_twin::CONDITION_LEVEL, causal_twin::FILTER, "meanabs"};
  dds::FactorMessage m = test::factor_message_head(id, k, "c" + std::to_string(k + 1), l.channels(), l.lag_order(),
                                                   index, kT0 + static_cast<std::int64_t>(index) * kStep);
  const int d = l.factor_count(k);
  m.factors = Eigen::VectorXd::Constant(d, 0.1);
  m.factor_std = Eigen::VectorXd::Constant(d, 0.5);
  for (int i = 0; i < d; ++i) m.factor_names.push_back(l.factor_name(k, i));
  m.innovation_count = 1;
  m.nis_mean = 1.0;
  m.last_innovation = 0.1;
  m.last_innovation_variance = 1.0;
  return m;
}

// 20 channels, a 400-snapshot window (what a dense VAR-LiNGAM order of 20 channels at lag 1 needs): all 400
// vectors arrive first, then the replayed factors, then the run goes on vector-then-factors.
TEST(ObservationAssemblerWindow, EveryVectorOfALongCalibrationWindowIsJoined) {
  constexpr int g = 20;
  constexpr std::uint64_t window = 400, total = 600;
  estimation::ModelSpec spec;
  spec.channels = g;
  spec.lag_order = 1;
  spec.include_self_lags = true;
  const estimation::SvarLayout l(spec);
  ObservationAssembler assembler;
  std::vector<AssembledObservation> out;
  auto vector_of = [&](std::uint64_t n) {
    const Eigen::VectorXd v = Eigen::VectorXd::Constant(g, 0.06 + 1e-5 * static_cast<double>(n));
    assembler.add_condition("wide", "meanabs", kT0 + static_cast<std::int64_t>(n) * kStep, v, false, out);
  };
  auto factors_of = [&](std::uint64_t n) {
    for (int k = 0; k < g; ++k) assembler.add_factors(message(l, k, n), out);
  };
  for (std::uint64_t n = 0; n < window; ++n) vector_of(n);
  EXPECT_TRUE(out.empty());
  for (std::uint64_t n = 0; n < window; ++n) factors_of(n);
  for (std::uint64_t n = window; n < total; ++n) {
    vector_of(n);
    factors_of(n);
  }
  assembler.flush(out);
  ASSERT_EQ(out.size(), total);
  for (std::uint64_t n = 0; n < total; ++n) {
    const auto& o = out[static_cast<std::size_t>(n)].observation;
    ASSERT_EQ(o.index, n);
    ASSERT_EQ(o.features.size(), g) << "snapshot " << n << " reached the engine without its condition vector";
    EXPECT_EQ(o.features[0], 0.06 + 1e-5 * static_cast<double>(n));
  }
  EXPECT_EQ(assembler.evicted_conditions(), 0u);
}

// An estimator that sends no factors at all: the vectors kept are bounded (8192) and every one dropped is counted.
TEST(ObservationAssemblerWindow, VectorsWithoutFactorsAreBoundedAndCounted) {
  ObservationAssembler assembler;
  std::vector<AssembledObservation> out;
  for (std::uint64_t n = 0; n < 8192 + 10; ++n) {
    assembler.add_condition("wide", "meanabs", kT0 + static_cast<std::int64_t>(n) * kStep, Eigen::VectorXd::Ones(2), false, out);
  }
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(assembler.evicted_conditions(), 10u);
}

}  // namespace
}  // namespace causal::recommender
