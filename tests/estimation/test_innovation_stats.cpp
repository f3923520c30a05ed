// InnovationAccumulator / InnovationStats: running means, ignored non-finite input, feeding from a filter.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "causal/estimation/innovation_stats.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"

namespace causal {
namespace {

TEST(InnovationAccumulator, MeansOfKnownValues) {
  estimation::InnovationAccumulator acc;
  EXPECT_TRUE(std::isnan(acc.mean()));
  acc.add(1.0, 2.0);   // e^2/s = 0.5
  acc.add(-3.0, 1.0);  // 9
  acc.add(2.0, 4.0);   // 1
  acc.add(std::numeric_limits<double>::quiet_NaN(), 1.0);
  acc.add(1.0, 0.0);
  EXPECT_EQ(acc.count(), 3u);
  EXPECT_DOUBLE_EQ(acc.mean(), 0.0);
  EXPECT_DOUBLE_EQ(acc.mean_square(), 14.0 / 3.0);
  EXPECT_DOUBLE_EQ(acc.mean_nis(), 10.5 / 3.0);
  acc.reset();
  EXPECT_EQ(acc.count(), 0u);
}

TEST(InnovationStats, FedFromFilter) {
  estimation::ModelSpec spec;
  spec.channels = 2;
  estimation::SvarLayout layout(spec);
  estimation::SvarKalmanFilter filter(layout, {estimation::NoiseParams{0.5, 1.0, 1.0}});
  estimation::InnovationStats stats(2);
  const double y0[] = {0.0, 1.0}, y1[] = {1.0, 1.0};
  filter.step(y0);
  filter.step(y1);
  stats.add(filter);
  // Same numbers as the hand-computed filter test: e = (1, 1), S = (4, 2.5).
  EXPECT_EQ(stats.outcome(0).count(), 1u);
  EXPECT_DOUBLE_EQ(stats.outcome(0).mean_nis(), 0.25);
  EXPECT_DOUBLE_EQ(stats.outcome(1).mean_nis(), 0.4);
}

TEST(InnovationStats, CheckpointKeepsTheRunningSumsAndChecksTheShape) {
  // An accumulator restored mid-way continues with the same sums (hand-computed means below).
  estimation::InnovationAccumulator a, b;
  a.add(1.0, 2.0);
  a.add(-3.0, 1.0);
  estimation::StateWriter w;
  a.save(w);
  estimation::StateReader r(w.bytes());
  b.restore(r);
  b.add(2.0, 4.0);
  a.add(2.0, 4.0);
  EXPECT_EQ(b.count(), 3u);
  EXPECT_DOUBLE_EQ(b.mean(), 0.0);                            // (1 - 3 + 2) / 3
  EXPECT_DOUBLE_EQ(b.mean_nis(), (0.5 + 9.0 + 1.0) / 3.0);    // hand-computed
  EXPECT_EQ(b.mean_square(), a.mean_square());

  // InnovationStats: one accumulator per outcome; a checkpoint of 2 outcomes does not fit 3.
  estimation::InnovationStats stats(2), same_shape(2);
  estimation::StateWriter ws;
  stats.save(ws);
  estimation::InnovationStats three(3);
  estimation::StateReader rs(ws.bytes());
  EXPECT_THROW(three.restore(rs), estimation::StateError);
  estimation::StateReader rs2(ws.bytes());
  EXPECT_NO_THROW(same_shape.restore(rs2));
  EXPECT_TRUE(rs2.at_end());
}

}  // namespace
}  // namespace causal
