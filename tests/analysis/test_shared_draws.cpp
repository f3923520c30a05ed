// Several what-if queries answered from one set of posterior draws (answer_interventions, DrawSharing::shared)
// give every query the same answer, bit for bit, as the per-query way (each query its own draws, every draw's
// dynamics by eigenvalues where the norms prove nothing) and as answer_intervention on it alone; and the proofs
// that let a draw skip the eigenvalues (linear_system.hpp prove_radius) never contradict them.
#include "causal/analysis/bounded_answer.hpp"
#include "causal/analysis/recommendation.hpp"

#include "../../common/analysis/src/linear_system.hpp"
#include "same_fields.hpp"

#include <gtest/gtest.h>

#include <causal/estimation/svar_layout.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>
#include <vector>

using namespace causal;
using namespace causal::analysis;

namespace {

constexpr int kG = 5;

estimation::SvarLayout layout_of() {
  estimation::ModelSpec spec;
  spec.channels = kG;
  spec.lag_order = 2;
  spec.include_self_lags = true;
  spec.instantaneous_allowed.assign(kG, std::vector<bool>(kG, false));
  for (int k = 1; k < kG; ++k) spec.instantaneous_allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(k - 1)] = true;
  return estimation::SvarLayout(spec);
}

// Self lag `self` on every channel, 0.3 at once from the channel before, 0.05 lagged from every other one; every
// factor with standard deviation `sd` (diagonal blocks).
FactorPosterior posterior_of(const estimation::SvarLayout& layout, double self, double sd) {
  FactorPosterior p;
  p.mean = Eigen::VectorXd::Zero(layout.total_factors());
  for (int k = 0; k < kG; ++k) {
    const auto& regs = layout.regressors(k);
    for (std::size_t i = 0; i < regs.size(); ++i) {
      double v = 0.0;
      if (regs[i].lag == 0) v = 0.3;
      if (regs[i].lag == 1) v = regs[i].channel == k ? self : 0.05;
      p.mean(layout.offset(k) + static_cast<int>(i)) = v;
    }
    p.blocks.push_back(sd * sd * Eigen::MatrixXd::Identity(layout.factor_count(k), layout.factor_count(k)));
  }
  return p;
}

std::vector<InterventionQuery> queries_of() {
  std::vector<InterventionQuery> q;
  for (int j = 1; j < kG; ++j) {
    InterventionQuery s;
    s.channel = j;
    s.delta = -0.1 * j;
    q.push_back(s);
  }
  InterventionQuery impulse;
  impulse.channel = 0;
  impulse.delta = 0.2;
  impulse.kind = InterventionKind::impulse;
  q.push_back(impulse);
  return q;
}

// Bit for bit, NaN equal to NaN.
void expect_same(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (std::isnan(a(i))) {
      EXPECT_TRUE(std::isnan(b(i))) << what << " " << i;
    } else {
      EXPECT_EQ(a(i), b(i)) << what << " " << i;
    }
  }
}

void expect_same(const BoundedAnswer& a, const BoundedAnswer& b) {
  EXPECT_SAME_FIELDS(a, b, kind, status, reason, horizon_snapshots, draws, unstable_draws, singular_draws,
                     draws_summarised);
  for (const EffectSummary* s : {&a.immediate, &a.effect}) {
    const EffectSummary& t = s == &a.immediate ? b.immediate : b.effect;
    expect_same(s->median, t.median, "median");
    expect_same(s->lower, t.lower, "lower");
    expect_same(s->upper, t.upper, "upper");
  }
}

}  // namespace

// Near a unit root (self lag 0.99 +- 0.02: a share of the draws settles, the rest does not) and well inside it
// (0.5: steady-state answers): shared draws, one query at a time, and answer_intervention alone agree exactly.
TEST(SharedDraws, EveryQueryGetsTheAnswerItGetsAlone) {
  const auto layout = layout_of();
  const auto queries = queries_of();
  UncertaintyOptions opt;
  opt.draws = 400;
  int unstable = 0, settled = 0, steady = 0;
  for (const double self : {0.99, 0.5}) {
    const auto posterior = posterior_of(layout, self, self > 0.9 ? 0.02 : 0.01);
    const auto shared = answer_interventions(layout, posterior, queries, AnswerRule{}, opt, DrawSharing::shared);
    const auto per_query = answer_interventions(layout, posterior, queries, AnswerRule{}, opt, DrawSharing::per_query);
    ASSERT_EQ(shared.size(), queries.size());
    ASSERT_EQ(per_query.size(), queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      SCOPED_TRACE("self lag " + std::to_string(self) + ", query " + std::to_string(i));
      expect_same(shared[i], per_query[i]);
      expect_same(shared[i], answer_intervention(layout, posterior, queries[i], AnswerRule{}, opt));
      unstable += shared[i].unstable_draws;
      settled += shared[i].draws - shared[i].unstable_draws - shared[i].singular_draws;
      steady += shared[i].kind == AnswerKind::steady_state;
    }
  }
  // Both kinds of draws and both kinds of answers were compared (else the case proves nothing).
  EXPECT_GT(unstable, 100);
  EXPECT_GT(settled, 100);
  EXPECT_GE(steady, 4);
}

TEST(SharedDraws, RankingIsTheSameEitherWay) {
  const auto layout = layout_of();
  const auto posterior = posterior_of(layout, 0.99, 0.02);
  RecommendationOptions shared, per_query;
  shared.uncertainty.draws = per_query.uncertainty.draws = 300;
  per_query.draw_sharing = DrawSharing::per_query;
  const std::vector<CandidateIntervention> candidates = {{1, -0.1}, {2, -0.2}, {3, -0.1}, {4, -0.3}};
  const auto a = rank_interventions(layout, posterior, 0, candidates, shared);
  const auto b = rank_interventions(layout, posterior, 0, candidates, per_query);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].action.channel, b[i].action.channel);
    EXPECT_EQ(a[i].text, b[i].text);
    expect_same(a[i].answer, b[i].answer);
  }
}

// A proof never contradicts the eigenvalues: "below" only where rho < bound, "at or above" only where rho >=
// bound; on matrices with a dominant real eigenvalue of 1.05 or more (a trending draw) instability IS proved.
TEST(RadiusProof, NeverContradictsTheEigenvaluesAndProvesTrendingDrawsUnstable) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double bound = detail::kUnstableRadius;
  int below = 0, above = 0, trending = 0, trending_proved = 0;
  for (int t = 0; t < 600; ++t) {
    const int n = 2 + t % 19;
    Eigen::MatrixXd m(n, n);
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
    if (t % 3 == 1) m = m.triangularView<Eigen::Upper>().toDenseMatrix();  // non-normal: ||m|| >> rho
    if (t % 3 == 2) {  // a trending draw: one self lag past 1 over small coupling
      m *= 0.02;
      m(0, 0) = 1.0 + 0.002 * (t % 100);
    }
    const double target = 0.5 + 0.002 * (t % 500);  // radius 0.5 .. 1.5 for the others
    const double rho0 = Eigen::EigenSolver<Eigen::MatrixXd>(m, false).eigenvalues().cwiseAbs().maxCoeff();
    if (t % 3 != 2) m *= target / rho0;
    const double rho = Eigen::EigenSolver<Eigen::MatrixXd>(m, false).eigenvalues().cwiseAbs().maxCoeff();
    const auto proof = detail::prove_radius(m, bound, true);
    if (proof == detail::RadiusProof::below) {
      ++below;
      EXPECT_LT(rho, bound) << "t " << t;
    }
    if (proof == detail::RadiusProof::at_or_above) {
      ++above;
      EXPECT_GE(rho, bound) << "t " << t;
    }
    EXPECT_EQ(detail::radius_proved_below(m, bound), proof == detail::RadiusProof::below);
    if (t % 3 == 2 && rho >= 1.05) {
      ++trending;
      trending_proved += proof == detail::RadiusProof::at_or_above;
    }
  }
  EXPECT_GT(below, 50);
  EXPECT_GT(above, 50);
  EXPECT_GT(trending, 20);
  EXPECT_EQ(trending_proved, trending);
}
