// What-if predictions against closed forms and against simulating the TRUE system under the intervention.
#include "causal/analysis/intervention.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "matrix_asserts.hpp"
#include "true_model.hpp"

using namespace causal::analysis;
using namespace causal::analysis::test;

namespace {

TEST(Intervention, TwoChannelClosedForm) {
  // y1 = 0.3 y1[n-1] + e1;  y2 = b y1 + 0.5 y2[n-1] + e2.
  const double b = 0.8;
  StructuralModel m = zero_model(2, 1);
  m.a0(1, 0) = b;
  m.lags[0](0, 0) = 0.3;
  m.lags[0](1, 1) = 0.5;
  InterventionQuery q;
  q.channel = 0;
  q.delta = -0.02;
  q.horizon = 3;
  const InterventionEffect e = predict_intervention(m, q);
  ASSERT_EQ(e.status, AnalysisStatus::ok) << e.message;
  EXPECT_DOUBLE_EQ(e.immediate(0), -0.02);
  EXPECT_NEAR(e.immediate(1), b * -0.02, 1e-15);
  EXPECT_NEAR(e.steady_state(1), b * -0.02 / (1.0 - 0.5), 1e-15);  // (1 - 0.5) d2 = b delta
  // Path: d2[1] = b delta + 0.5 d2[0], d2[2] = b delta + 0.5 d2[1].
  EXPECT_NEAR(e.path(1, 1), b * -0.02 * 1.5, 1e-15);
  EXPECT_NEAR(e.path(2, 1), b * -0.02 * 1.75, 1e-15);
  EXPECT_NEAR(e.spectral_radius, 0.5, 1e-12);  // channel 1 cut: only the 0.5 root is left
  EXPECT_EQ(e.cumulative.size(), 0);

  // Intervening on the effect does not move the cause.
  q.channel = 1;
  const InterventionEffect up = predict_intervention(m, q);
  EXPECT_EQ(up.immediate(0), 0.0);
  EXPECT_EQ(up.steady_state(0), 0.0);

  // Impulse on the cause: immediate the same, decays to 0; cumulative from geometric sums:
  // d1[n] = delta 0.3^n (sum delta/0.7), d2 obeys d2[n] = b d1[n] + 0.5 d2[n-1] -> sum = b delta/(0.7 * 0.5).
  q.channel = 0;
  q.kind = InterventionKind::impulse;
  const InterventionEffect imp = predict_intervention(m, q);
  ASSERT_EQ(imp.status, AnalysisStatus::ok) << imp.message;
  EXPECT_NEAR(imp.immediate(1), b * -0.02, 1e-15);
  EXPECT_TRUE(imp.steady_state.isZero());
  EXPECT_NEAR(imp.cumulative(0), -0.02 / 0.7, 1e-14);
  EXPECT_NEAR(imp.cumulative(1), b * -0.02 / (0.7 * 0.5), 1e-14);
  EXPECT_NEAR(imp.path(1, 0), -0.02 * 0.3, 1e-15);
}

// Mean change of the TRUE system under do(): average over R noise realisations of (intervened - baseline),
// simulated by substitution (svar_sim.hpp), from n0 on.
Eigen::MatrixXd simulated_change(const TrueSvar& s, int j, double delta, bool sustained, int n0, int length,
                                 std::mt19937_64& rng, int realisations) {
  const int g = static_cast<int>(s.a0.rows());
  const int n = n0 + length;
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(length, g);
  for (int r = 0; r < realisations; ++r) {
    const Eigen::MatrixXd e = draw_noise(rng, n, Eigen::VectorXd::Ones(g), NoiseKind::laplace);
    const Eigen::MatrixXd base = simulate(s, e);
    Eigen::MatrixXd forced = no_force(n, g);
    for (int t = n0; t < (sustained ? n : n0 + 1); ++t) forced(t, j) = base(t, j) + delta;
    mean += (simulate(s, e, &forced) - base).bottomRows(length);
  }
  return mean / realisations;
}

TEST(Intervention, MatchesSimulationOfTrueSystem) {
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 3; ++trial) {
    const TrueSvar truth = random_svar(rng, 4, 2, 0.3, 0.7, 0.4, 0.2);
    const StructuralModel m = model_of(truth);
    for (int j = 0; j < 4; ++j) {
      for (bool sustained : {true, false}) {
        InterventionQuery q;
        q.channel = j;
        q.delta = 0.5;
        q.kind = sustained ? InterventionKind::sustained : InterventionKind::impulse;
        q.horizon = 400;
        const InterventionEffect e = predict_intervention(m, q);
        ASSERT_EQ(e.status, AnalysisStatus::ok) << e.message;
        const Eigen::MatrixXd sim = simulated_change(truth, j, 0.5, sustained, 50, 400, rng, 5);
        EXPECT_MATRIX_NEAR(e.immediate, sim.row(0).transpose(), 1e-10);
        EXPECT_MATRIX_NEAR(e.path, sim, 1e-10);
        // 400 samples after n0 the change has settled (radius <= 0.9: 0.9^400 ~ 5e-19).
        EXPECT_MATRIX_NEAR(e.steady_state, sim.row(399).transpose(), 1e-9);
        if (!sustained) {
          EXPECT_MATRIX_NEAR(e.cumulative, sim.colwise().sum().transpose(), 1e-9);
        }
      }
    }
  }
}

TEST(Intervention, UnstableIntervenedSystemIsAStatus) {
  // Channel 0 is a random walk (unit root); intervening on channel 1 leaves it in place.
  StructuralModel m = zero_model(2, 1);
  m.lags[0](0, 0) = 1.0;
  m.a0(1, 0) = 0.5;
  m.a0(0, 1) = 0.0;
  m.lags[0](1, 1) = 0.2;
  m.lags[0](0, 1) = 0.3;
  InterventionQuery q;
  q.channel = 1;
  q.delta = 1.0;
  const InterventionEffect e = predict_intervention(m, q);
  EXPECT_EQ(e.status, AnalysisStatus::unstable);
  EXPECT_FALSE(e.message.empty());
  EXPECT_NEAR(e.spectral_radius, 1.0, 1e-9);
  EXPECT_TRUE(e.immediate.allFinite());  // the immediate change needs no stability
  EXPECT_TRUE(std::isnan(e.steady_state(0)));
  // Intervening on channel 0 itself removes the unit root: fine.
  q.channel = 0;
  EXPECT_EQ(predict_intervention(m, q).status, AnalysisStatus::ok);
  // An explosive original system makes the impulse response diverge.
  m.lags[0](0, 0) = 1.3;
  q.channel = 1;
  q.kind = InterventionKind::impulse;
  EXPECT_EQ(predict_intervention(m, q).status, AnalysisStatus::unstable);
}

TEST(Intervention, SingularInstantaneousLoopIsNotIdentifiable) {
  // y2 = y3 + ..., y3 = y2 + ...: a two-way instantaneous link with loop gain 1.
  StructuralModel m = zero_model(3, 1);
  m.a0(1, 2) = 1.0;
  m.a0(2, 1) = 1.0;
  m.a0(1, 0) = 0.5;
  InterventionQuery q;
  q.channel = 0;
  q.delta = 1.0;
  InterventionEffect e = predict_intervention(m, q);
  EXPECT_EQ(e.status, AnalysisStatus::not_identifiable);
  EXPECT_FALSE(e.message.empty());
  EXPECT_TRUE(std::isnan(e.immediate(1)));
  // Holding channel 1 breaks the loop: identifiable.
  q.channel = 1;
  e = predict_intervention(m, q);
  EXPECT_EQ(e.status, AnalysisStatus::ok) << e.message;
  EXPECT_NEAR(e.immediate(2), 1.0, 1e-15);
  // As an impulse the original (looped) equations drive the aftermath: immediate ok, rest not identifiable.
  q.kind = InterventionKind::impulse;
  q.horizon = 2;
  e = predict_intervention(m, q);
  EXPECT_EQ(e.status, AnalysisStatus::not_identifiable);
  EXPECT_TRUE(e.immediate.allFinite());
  EXPECT_TRUE(std::isnan(e.path(1, 0)));
}

TEST(Intervention, BadQueries) {
  const StructuralModel m = zero_model(2, 1);
  InterventionQuery q;
  q.channel = 2;
  EXPECT_THROW(predict_intervention(m, q), std::invalid_argument);
  q.channel = 0;
  q.horizon = -1;
  EXPECT_THROW(predict_intervention(m, q), std::invalid_argument);
  q.horizon = 0;
  q.delta = std::numeric_limits<double>::infinity();
  EXPECT_EQ(predict_intervention(m, q).status, AnalysisStatus::non_finite_input);
}

}  // namespace
