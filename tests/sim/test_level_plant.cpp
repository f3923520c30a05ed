// sensor-sim's condition-level plant: the do-operation (P2) an approved intervention applies, checked against the
// what-if recursion (W1) of common/analysis/intervention.hpp written out here for the plant's own matrices; same
// input, same output; what cannot be applied as approved is refused.
#include "level_plant.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using causal::sim::LevelIntervention;
using causal::sim::LevelPlant;
using causal::sim::PlantKind;

namespace {

std::vector<Eigen::VectorXd> run(LevelPlant& plant, int n) {
  std::vector<Eigen::VectorXd> out;
  for (int i = 0; i < n; ++i) out.push_back(plant.next());
  return out;
}

// (W1) for the plant's VAR(1), equation j cut while the intervention holds, original equations after it:
// d[n] = A0c d[n] + A1c d[n-1] + e_j delta inside the window, d[n] = A0 d[n] + A1 d[n-1] after it.
std::vector<Eigen::Vector3d> expected_effect(const LevelPlant& p, int j, double delta, int duration, int n) {
  std::vector<Eigen::Vector3d> d;
  Eigen::Vector3d prev = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d now = Eigen::Vector3d::Zero();
    for (int k : {1, 0, 2}) {
      if (k == j && i < duration) {
        now[k] = delta;
      } else {
        now[k] = p.a0().row(k).dot(now) + p.a1().row(k).dot(prev);
      }
    }
    d.push_back(now);
    prev = now;
  }
  return d;
}

}  // namespace

TEST(LevelPlant, SameInputSameOutput) {
  LevelPlant a(PlantKind::lever, 7, 0), b(PlantKind::lever, 7, 0), c(PlantKind::lever, 8, 0);
  LevelIntervention iv{1, -30.0, 100, 20};
  ASSERT_EQ(a.add(iv), "");
  run(b, 50);  // b learns of the same intervention later, still before its start
  ASSERT_EQ(b.add(iv), "");
  const auto ya = run(a, 300);
  LevelPlant b_fresh(PlantKind::lever, 7, 0);
  ASSERT_EQ(b_fresh.add(iv), "");
  const auto yb = run(b_fresh, 300);
  for (int n = 0; n < 300; ++n) EXPECT_EQ(ya[n], yb[n]) << n;
  EXPECT_NE(run(c, 1)[0], ya[0]);
}

TEST(LevelPlant, InterventionIsTheWhatIfDoOperation) {
  for (PlantKind kind : {PlantKind::lever, PlantKind::no_lever, PlantKind::near_unit_root}) {
    LevelPlant with(kind, 3, 1), without(kind, 3, 1);
    const int start = 260, duration = 24;
    const double delta = std::log1p(-0.4);
    ASSERT_EQ(with.add(LevelIntervention{1, -40.0, static_cast<std::uint64_t>(start), static_cast<std::uint64_t>(duration)}), "");
    const auto y = run(with, 340), y0 = run(without, 340);
    const auto d = expected_effect(with, 1, delta, duration, 340 - start);
    for (int n = 0; n < 340; ++n) {
      const Eigen::Vector3d observed = (y[n].array().log() - y0[n].array().log()).matrix();
      const Eigen::Vector3d truth = n < start ? Eigen::Vector3d::Zero() : d[static_cast<std::size_t>(n - start)];
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(observed[k], truth[k], 1e-12) << to_string(kind) << " n=" << n << " k=" << k;
    }
    // The plant's own record of the true effect (last snapshot) is the same.
    EXPECT_NEAR(with.true_effect()[0], d.back()[0], 1e-12);
    if (kind == PlantKind::no_lever) {
      EXPECT_EQ(d[5][0], 0.0) << "no path from channel 2 to channel 1";
    } else {
      EXPECT_LT(d[5][0], -0.5) << "channel 1 follows channel 2's cut";
    }
  }
}

TEST(LevelPlant, RefusesWhatCannotBeAppliedAsApproved) {
  LevelPlant p(PlantKind::lever, 1, 0);
  run(p, 10);
  EXPECT_NE(p.add(LevelIntervention{1, -10.0, 9, 5}).find("late"), std::string::npos);
  EXPECT_NE(p.add(LevelIntervention{3, -10.0, 20, 5}), "");
  EXPECT_NE(p.add(LevelIntervention{1, -100.0, 20, 5}), "");
  EXPECT_NE(p.add(LevelIntervention{1, -10.0, 20, 0}), "");
  EXPECT_EQ(p.add(LevelIntervention{1, -10.0, 20, 5}), "");
  EXPECT_NE(p.add(LevelIntervention{1, -20.0, 22, 5}).find("overlaps"), std::string::npos);
  EXPECT_EQ(p.add(LevelIntervention{0, -20.0, 22, 5}), "");  // another channel may overlap
  EXPECT_EQ(p.interventions().size(), 2u);
}
