#include "causal/analysis/recommendation.hpp"

#include <gtest/gtest.h>

#include <causal/estimation/svar_layout.hpp>

#include <cmath>
#include <utility>

#include "matrix_asserts.hpp"

using causal::estimation::ModelSpec;
using causal::estimation::SvarLayout;
using namespace causal::analysis;

namespace {

const std::vector<std::string> kNames{"bearing 1", "bearing 2", "vibration at bearing 3"};

// A steady-state answer to moving `channel` by `delta`: effect within [lower, upper] at `coverage`,
// `immediate` at once.
Recommendation steady_state(int channel, double delta, double effect, std::pair<double, double> interval,
                            double immediate, double coverage) {
  Recommendation rec;
  rec.action = {channel, delta};
  rec.answer.kind = AnswerKind::steady_state;
  rec.effect = rec.steady_state = effect;
  rec.lower = interval.first;
  rec.upper = interval.second;
  rec.immediate = immediate;
  rec.interval_valid = true;
  rec.coverage = coverage;
  return rec;
}

TEST(Recommendation, SentenceMatchesTheHouseExample) {
  Recommendation rec = steady_state(2, -0.02, -0.015, {-0.019, -0.010}, -0.008, 0.9);
  EXPECT_EQ(describe_recommendation(rec, 0, kNames, "g"),
            "Reduce vibration at bearing 3 by 0.02 g: bearing 1 is predicted to drop by 0.015 g (90% interval "
            "0.010..0.019) at steady state, 0.008 at once.");
}

TEST(Recommendation, NarrowIntervalsGetMoreDecimals) {
  Recommendation rec = steady_state(1, -0.000923, -0.00171, {-0.00175, -0.00168}, -0.0008, 0.9);
  EXPECT_EQ(describe_recommendation(rec, 3, {"b1", "b2", "b3", "b4"}, "g"),
            "Reduce b2 by 0.000923 g: b4 is predicted to drop by 0.00171 g (90% interval 0.00168..0.00175) at steady "
            "state, 0.00080 at once.");
}

TEST(Recommendation, SentencesForRisesHorizonUncertainAndRefusedCases) {
  Recommendation rec = steady_state(1, 0.5, 1.2, {-0.1, 2.4}, 0.0, 0.95);
  const std::string up = describe_recommendation(rec, 0, {}, "");
  EXPECT_EQ(up,
            "Raise channel 2 by 0.5: channel 1 is predicted to rise by 1.2 (95% interval -0.1..2.4) at steady state, "
            "no change at once. The interval includes no change: the direction of the effect is uncertain.");
  rec.answer.kind = AnswerKind::horizon;
  rec.answer.horizon_snapshots = 12;
  rec.steady_state = std::nan("");
  EXPECT_NE(describe_recommendation(rec, 0, {}, "").find("after 12 snapshots (no reliable steady state)"), std::string::npos);
  rec.answer.kind = AnswerKind::refused;
  rec.interval_valid = false;
  rec.message = "past a unit root";
  EXPECT_NE(describe_recommendation(rec, 0, {}, "").find("cannot be predicted (past a unit root)"), std::string::npos);
}

// Target y1 = 0.5 y2 + 0.4 y1[n-1] + e1; y2 = 0.8 y3 + e2; y3 = e3 (no other links). A sustained shift of y2
// by d moves y1 by 0.5 d at once and by 0.5 d / (1 - 0.4) at steady state; a shift of y3 by d moves y2 by
// 0.8 d (no self lag: at once and for ever), so y1 by 0.4 d at once and 0.4 d / 0.6 at steady state.
TEST(Recommendation, RanksByPredictedSteadyStateReduction) {
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  spec.include_self_lags = true;
  spec.instantaneous_allowed = {{false, true, false}, {false, false, true}, {false, false, false}};
  const causal::estimation::SvarLayout layout(spec);
  FactorPosterior post;
  post.mean = Eigen::VectorXd::Zero(layout.total_factors());
  post.mean(layout.offset(0) + layout.factor_index(0, 1, 0)) = 0.5;
  post.mean(layout.offset(0) + layout.factor_index(0, 0, 1)) = 0.4;
  post.mean(layout.offset(1) + layout.factor_index(1, 2, 0)) = 0.8;
  for (int k = 0; k < 3; ++k) {
    post.blocks.push_back(1e-6 * Eigen::MatrixXd::Identity(layout.factor_count(k), layout.factor_count(k)));
  }
  RecommendationOptions opt;
  opt.channel_names = kNames;
  opt.unit = "g";
  opt.uncertainty.draws = 500;
  const std::vector<Recommendation> recs = rank_interventions(layout, post, 0, {{2, -0.1}, {1, -0.1}}, opt);
  ASSERT_EQ(recs.size(), 2u);
  // Reducing y2 by 0.1: target -0.05 at once, -0.05/0.6 at steady state. Reducing y3 by 0.1: -0.04, -0.04/0.6.
  // The point is the median of draws with factor sd 1e-3: within 1e-3 of the closed form.
  EXPECT_EQ(recs[0].action.channel, 1);
  EXPECT_NEAR(recs[0].steady_state, -0.05 / 0.6, 1e-3);
  EXPECT_NEAR(recs[0].immediate, -0.05, 1e-3);
  EXPECT_EQ(recs[1].action.channel, 2);
  EXPECT_NEAR(recs[1].steady_state, -0.04 / 0.6, 1e-3);
  for (const auto& r : recs) {
    EXPECT_EQ(r.status, AnalysisStatus::ok);
    EXPECT_EQ(r.answer.kind, AnswerKind::steady_state);
    EXPECT_TRUE(r.interval_valid);
    EXPECT_TRUE(r.reliable);
    EXPECT_LE(r.lower, r.steady_state);
    EXPECT_GE(r.upper, r.steady_state);
    EXPECT_DOUBLE_EQ(r.coverage, 0.9);
  }
  EXPECT_EQ(recs[0].text.rfind("Reduce bearing 2 by 0.1 g: bearing 1 is predicted to drop by 0.08", 0), 0u) << recs[0].text;
  EXPECT_NE(recs[0].text.find(") at steady state, 0.0500 at once."), std::string::npos) << recs[0].text;

  EXPECT_THROW(rank_interventions(layout, post, 0, {{0, -0.1}}, opt), std::invalid_argument);
  EXPECT_THROW(rank_interventions(layout, post, 3, {{1, -0.1}}, opt), std::invalid_argument);
  opt.channel_names = {"a"};
  EXPECT_THROW(rank_interventions(layout, post, 0, {{1, -0.1}}, opt), std::invalid_argument);
}

// Ranking rule: by the interval bound in the helpful direction, and an interval that includes no change is
// never ranked as if it helped. y1 = 0.6 y2 + 0.3 y3 + e1 (no lags): cutting y2 by 0.1 gives -0.06 but with a
// wide interval (sd of x12 = 0.5: upper bound > 0); cutting y3 by 0.1 gives -0.03 with a narrow one.
TEST(Recommendation, RanksByTheHelpfulBoundAndNeverRecommendsAnUnsureLever) {
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  spec.instantaneous_allowed = {{false, true, true}, {false, false, false}, {false, false, false}};
  const causal::estimation::SvarLayout layout(spec);
  FactorPosterior post;
  post.mean = Eigen::VectorXd::Zero(layout.total_factors());
  const int i12 = layout.factor_index(0, 1, 0), i13 = layout.factor_index(0, 2, 0);
  post.mean(layout.offset(0) + i12) = 0.6;
  post.mean(layout.offset(0) + i13) = 0.3;
  for (int k = 0; k < 3; ++k) post.blocks.push_back(Eigen::MatrixXd::Zero(layout.factor_count(k), layout.factor_count(k)));
  post.blocks[0](i12, i12) = 0.5 * 0.5;
  post.blocks[0](i13, i13) = 0.01 * 0.01;
  RecommendationOptions opt;
  opt.uncertainty.draws = 1000;
  const auto recs = rank_interventions(layout, post, 0, {{1, -0.1}, {2, -0.1}}, opt);
  ASSERT_EQ(recs.size(), 2u);
  // Closed form: y2 cut -> 0.6 * -0.1 = -0.06, 90 % interval -0.06 -/+ 1.645 * 0.05 = [-0.142, +0.022].
  EXPECT_EQ(recs[0].action.channel, 2) << "the sure, smaller reduction ranks first";
  EXPECT_TRUE(recs[0].reliable);
  EXPECT_NEAR(recs[0].effect, -0.03, 3e-4);
  EXPECT_EQ(recs[1].action.channel, 1);
  EXPECT_FALSE(recs[1].reliable) << recs[1].text;
  EXPECT_NEAR(recs[1].effect, -0.06, 0.01);
  EXPECT_NEAR(recs[1].upper, -0.06 + 1.645 * 0.05, 0.01);
  EXPECT_GT(recs[1].upper, 0.0);
  EXPECT_NE(recs[1].text.find("direction of the effect is uncertain"), std::string::npos) << recs[1].text;
  for (const auto& r : recs) {
    EXPECT_LE(r.lower, r.effect);
    EXPECT_GE(r.upper, r.effect);
  }
}

TEST(Recommendation, CandidatesFromExcess) {
  const Eigen::Vector3d current(0.5, 0.3, 0.1);
  const Eigen::Vector3d baseline(0.2, 0.1, 0.2);
  const auto c = candidates_from_excess(current, baseline, 0, 0.5);
  ASSERT_EQ(c.size(), 1u);  // channel 0 is the target, channel 2 is below baseline
  EXPECT_EQ(c[0].channel, 1);
  EXPECT_NEAR(c[0].delta, -0.1, 1e-15);
  EXPECT_THROW(candidates_from_excess(current, baseline, 0, 0.0), std::invalid_argument);
  EXPECT_THROW(candidates_from_excess(current, Eigen::Vector2d(1, 1), 0, 1.0), std::invalid_argument);
}

TEST(Recommendation, DecimalsFollowMagnitude) {
  EXPECT_EQ(decimals_for(0.015), 3);
  EXPECT_EQ(decimals_for(1.5), 1);
  EXPECT_EQ(decimals_for(150.0), 0);
  EXPECT_EQ(decimals_for(0.0), 3);
}

}  // namespace
