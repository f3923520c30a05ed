// Effects in readable units (effect_units.hpp): percent of the current level, bounded below by -100 % for
// log-level and raw models, capped in the text, impossible reductions refused, and the one-line summary.
#include "causal/analysis/effect_units.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace causal::analysis;

namespace {

const EffectUnits kLog{true, ""};
const EffectUnits kRaw{false, "g"};

TEST(EffectUnits, LogLevelPercentIsExpMinusOneAndNeverBelowMinus100) {
  EXPECT_NEAR(percent_of_level(std::log(0.9), 0.2, kLog), -10.0, 1e-12);
  EXPECT_NEAR(percent_of_level(std::log(1.5), 0.2, kLog), 50.0, 1e-12);
  // The "-100 % (drop 12 log-level)" case: a huge drop approaches, never passes, -100 %.
  for (double d : {-12.0, -50.0, -1e3}) {
    EXPECT_GE(percent_of_level(d, 0.2, kLog), -100.0) << d;
    EXPECT_LT(percent_of_level(d, 0.2, kLog), -99.99) << d;
  }
  EXPECT_NEAR(level_change(std::log(0.9), 0.2, kLog), -0.02, 1e-15);
  EXPECT_TRUE(std::isnan(percent_of_level(NAN, 0.2, kLog)));
}

TEST(EffectUnits, RawLevelPercentIsRelativeToTheCurrentLevelWithAFloor) {
  EXPECT_NEAR(percent_of_level(-0.05, 0.2, kRaw), -25.0, 1e-12);
  EXPECT_DOUBLE_EQ(percent_of_level(-0.5, 0.2, kRaw), -100.0) << "a level cannot fall below 0";
  EXPECT_TRUE(std::isnan(percent_of_level(-0.05, 0.0, kRaw))) << "no percent of a zero level";
  EXPECT_DOUBLE_EQ(level_change(-0.05, 0.2, kRaw), -0.05);
}

TEST(EffectUnits, TextIsCappedAndSigned) {
  EXPECT_EQ(percent_text(-8.14), "-8.1 %");
  EXPECT_EQ(percent_text(3.0), "+3.0 %");
  EXPECT_EQ(percent_text(62258536684043.5), "> +1000 %");  // the recommendation
  EXPECT_EQ(percent_text(NAN), "n/a");
}

TEST(EffectUnits, MoreThanAHundredPercentReductionOfAPositiveLevelIsImpossible) {
  EXPECT_EQ(impossible_intervention(-0.1, 0.2, kRaw), "");
  EXPECT_NE(impossible_intervention(-0.3, 0.2, kRaw).find("below zero"), std::string::npos);
  EXPECT_EQ(impossible_intervention(-30.0, 0.2, kLog), "") << "any log change keeps the level positive";
  EXPECT_NE(impossible_intervention(NAN, 0.2, kLog), "");
}

BoundedAnswer answer_with(AnswerKind kind, double median, double lower, double upper) {
  BoundedAnswer a;
  a.kind = kind;
  a.horizon_snapshots = kind == AnswerKind::horizon ? 12 : 0;
  a.spectral_radius = kind == AnswerKind::horizon ? 0.993 : 0.93;
  a.draws = 400;
  a.unstable_draws = kind == AnswerKind::horizon ? 37 : 0;
  a.coverage = 0.9;
  a.effect.median = Eigen::Vector2d(0.0, median);
  a.effect.lower = Eigen::Vector2d(0.0, lower);
  a.effect.upper = Eigen::Vector2d(0.0, upper);
  return a;
}

TEST(EffectUnits, OneLineCarriesHorizonIntervalConfidenceAndStability) {
  const BoundedAnswer h = answer_with(AnswerKind::horizon, std::log(0.919), std::log(0.88), std::log(0.961));
  EXPECT_EQ(answer_line(h, 1, 0.2, kLog),
            "after 12 snapshots: -8.1 % [-12.0, -3.9] (90 %), model near a unit root rho=0.993, 37/400 draws unstable");
  const BoundedAnswer s = answer_with(AnswerKind::steady_state, std::log(0.919), std::log(0.88), std::log(0.961));
  EXPECT_EQ(answer_line(s, 1, 0.2, kLog),
            "at steady state: -8.1 % [-12.0, -3.9] (90 %), model stable rho=0.930, 0/400 draws unstable");
  BoundedAnswer r;
  r.reason = "the model is past a unit root";
  EXPECT_EQ(answer_line(r, 1, 0.2, kLog), "refused: the model is past a unit root");
  // Raw model predicting a fall below zero: the interval reaches -100 %, so the level could vanish or stay
  // at 75 %: no number says that honestly.
  const BoundedAnswer below = answer_with(AnswerKind::steady_state, -0.1, -0.3, -0.05);
  EXPECT_EQ(answer_line(below, 1, 0.2, kRaw),
            "at steady state: effect unknown (the 90 % interval reaches -100 %), model stable rho=0.930, 0/400 draws "
            "unstable");
}

TEST(EffectUnits, IntervalWiderThanAFactorOfTenIsEffectUnknown) {
  // +687 % [-40, +2400]: upper / lower level = 25 / 0.6 = 41.7 > 10.
  const BoundedAnswer wide = answer_with(AnswerKind::horizon, std::log(7.87), std::log(0.6), std::log(25.0));
  EXPECT_EQ(answer_line(wide, 1, 0.2, kLog),
            "after 12 snapshots: effect unknown (the 90 % interval spans a factor of 42 in level), model near a unit "
            "root rho=0.993, 37/400 draws unstable");
  // Just inside the rule (factor 9.5): the numbers are given.
  const BoundedAnswer narrow = answer_with(AnswerKind::horizon, std::log(2.0), std::log(0.5), std::log(4.75));
  EXPECT_NE(answer_line(narrow, 1, 0.2, kLog).find("+100.0 % [-50.0, +375.0]"), std::string::npos);
  EXPECT_DOUBLE_EQ(interval_level_factor(-50.0, 375.0), 9.5);
  EXPECT_TRUE(std::isinf(interval_level_factor(-100.0, 10.0)));
}

TEST(EffectUnits, NoFigureBeyondTheDisplayCap) {
  // The IMS answer "+455.8 % [+170.1, > +1000]" spans a factor of 9.96 in level (inside the width rule) but its
  // upper end cannot be stated as a figure: unknown, with the reason.
  EXPECT_EQ(effect_unknown_reason(170.1, 1031.0, 0.9), "the 90 % interval reaches beyond +1000 %");
  const BoundedAnswer high = answer_with(AnswerKind::horizon, std::log(5.558), std::log(2.701), std::log(11.31));
  EXPECT_EQ(answer_line(high, 1, 0.2, kLog),
            "after 12 snapshots: effect unknown (the 90 % interval reaches beyond +1000 %), model near a unit root "
            "rho=0.993, 37/400 draws unstable");
  // Raw log effects of 4.72 (+11,110 % of the level): unknown, not a figure.
  EXPECT_NE(effect_unknown_reason(100.0 * std::expm1(4.6), 100.0 * std::expm1(4.72), 0.9), "");
  // Inside every rule: stated.
  EXPECT_EQ(effect_unknown_reason(-12.0, -3.9, 0.9), "");
  EXPECT_EQ(effect_unknown_reason(150.0, 1000.0, 0.9), "");
  EXPECT_EQ(effect_unknown_reason(-50.0, 375.0, 0.9), "");
  EXPECT_EQ(effect_unknown_reason(-60.0, 2300.0, 0.9), "the 90 % interval spans a factor of 60 in level");
  EXPECT_EQ(effect_unknown_reason(-100.0, 10.0, 0.9), "the 90 % interval reaches -100 %");
  EXPECT_EQ(effect_unknown_reason(NAN, 10.0, 0.9), "the 90 % interval is not finite");
  // causal-ask knows the bounds but not their coverage (the reply does not carry it): the same decision, worded
  // without a level.
  EXPECT_EQ(effect_unknown_reason(170.1, 1031.0, NAN), "the interval reaches beyond +1000 %");
  EXPECT_EQ(effect_unknown_reason(-60.0, 2300.0, NAN), "the interval spans a factor of 60 in level");
  EXPECT_EQ(effect_unknown_reason(-12.0, -3.9, NAN), "");
}

TEST(EffectUnits, HorizonInHoursAtTheGroupsCadence) {
  EffectUnits u;
  u.snapshot_hours = 1.0 / 6.0;  // 10-minute snapshots
  const BoundedAnswer h = answer_with(AnswerKind::horizon, std::log(0.919), std::log(0.88), std::log(0.961));
  EXPECT_EQ(answer_line(h, 1, 0.2, u).substr(0, 30), "after 12 snapshots (2.0 h): -8");
}

}  // namespace
