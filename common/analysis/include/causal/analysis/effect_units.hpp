// Effects in units a person can read: the channel's own units and percent of its current level, and the
// one line every what-if answer and recommendation carries.
//
// Log-level models (the estimator's log_transform): an effect d on log(y) changes the level by
// y (e^d - 1), i.e. 100 (e^d - 1) %: bounded below by -100 % (a positive quantity cannot fall below 0),
// unbounded above; above kPercentDisplayCap the text says "> +1000 %" instead of a meaningless number.
// Raw-level models: d is already in the channel's units; percent = 100 d / y, and a predicted fall below
// zero is shown as -100 % with a note (the linear model knows no floor; the level does).
#pragma once

#include "causal/analysis/bounded_answer.hpp"

#include <limits>
#include <string>

namespace causal::analysis {

inline constexpr double kPercentDisplayCap = 1000.0;
// An effect whose interval spans more than this factor in level (upper level / lower level) is "effect
// unknown": "+687 % [-60, +2400]" tells an engineer nothing a number could honestly say.
inline constexpr double kMaxKnownLevelFactor = 10.0;

struct EffectUnits {
  bool log_level = true;  // the model runs on log(feature)
  std::string unit;       // of the raw feature, e.g. "g"; may be empty
  double snapshot_hours = std::numeric_limits<double>::quiet_NaN();  // the cadence, for horizons in hours
};

// Upper over lower level of an interval given in percent of the current level; +inf when the lower end is
// at or below -100 % (the level could vanish) or either end is not finite.
double interval_level_factor(double percent_lower, double percent_upper);

// The one decision whether an effect interval (in percent of the level) may be stated as a number: every
// what-if answer of the live twin (answer_line, Advisor::what_if) and of causal-whatif goes through it.
// Returns "" when it may, else why not, e.g. "the 90 % interval spans a factor of 37 in level". Unknown when
// the interval spans more than kMaxKnownLevelFactor in level, reaches -100 % (the level could vanish), is
// not finite, or reaches beyond +-kPercentDisplayCap (a bound no figure can state: "> +1000 %" would hide
// how far beyond it goes). A non-finite coverage (causal-ask: the reply carries the bounds, not their
// level) words the reason "the interval ..." instead of "the 90 % interval ...".
std::string effect_unknown_reason(double percent_lower, double percent_upper, double coverage);

// Percent change of a level `current` (> 0) for a model-unit effect. Log-level: 100 expm1(d) (> -100);
// raw: 100 d / current, NaN when current is not positive and finite. Never below -100.
double percent_of_level(double model_effect, double current, const EffectUnits& units);
// Change in the channel's own units: log-level current expm1(d); raw: d.
double level_change(double model_effect, double current, const EffectUnits& units);
// "-8.1 %", "> +1000 %", "n/a" (non-finite).
std::string percent_text(double percent);

// Checks that an intervention of `delta` (model units) on a channel at `current` is possible: a raw-level
// model cannot reduce a positive quantity by more than 100 % (delta < -current). Returns "" when it is,
// else the reason.
std::string impossible_intervention(double delta, double current, const EffectUnits& units);

// "stable" (steady-state answer), "near a unit root" (rho >= 0.95), "not reliably stable" (a horizon answer
// because of the unstable draws), "past a unit root" (rho >= 1).
const char* stability_words(const BoundedAnswer& answer);

// The one line, e.g.
//   "after 12 snapshots (2.0 h): -8.1 % [-12.0, -3.9] (90 %), model near a unit root rho=0.993, 37/400 draws unstable"
//   "after 12 snapshots (2.0 h): effect unknown (the 90 % interval spans a factor of 37 in level), model ..."
//   "at steady state: -8.1 % [-12.0, -3.9] (90 %), model stable rho=0.93, 0/400 draws unstable"
//   "refused: <reason>"
// for `channel`, whose current level is `current` (raw feature units).
std::string answer_line(const BoundedAnswer& answer, int channel, double current, const EffectUnits& units);

}  // namespace causal::analysis
