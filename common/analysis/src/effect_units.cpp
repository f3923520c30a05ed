#include "causal/analysis/effect_units.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace causal::analysis {

double percent_of_level(double model_effect, double current, const EffectUnits& units) {
  if (!std::isfinite(model_effect)) return std::numeric_limits<double>::quiet_NaN();
  if (units.log_level) return 100.0 * std::expm1(model_effect);  // > -100 for any finite effect
  if (!(current > 0.0) || !std::isfinite(current)) return std::numeric_limits<double>::quiet_NaN();
  return std::max(-100.0, 100.0 * model_effect / current);
}

double level_change(double model_effect, double current, const EffectUnits& units) {
  if (!units.log_level) return model_effect;
  if (!(current > 0.0) || !std::isfinite(current)) return std::numeric_limits<double>::quiet_NaN();
  return current * std::expm1(model_effect);
}

std::string percent_text(double percent) {
  if (!std::isfinite(percent)) return "n/a";
  char buf[48];
  if (percent > kPercentDisplayCap) {
    std::snprintf(buf, sizeof buf, "> +%.0f %%", kPercentDisplayCap);
  } else {
    std::snprintf(buf, sizeof buf, "%+.1f %%", percent);
  }
  return buf;
}

std::string impossible_intervention(double delta, double current, const EffectUnits& units) {
  if (!std::isfinite(delta)) return "the intervention size is not finite";
  if (units.log_level) return "";  // any finite log change keeps the level positive
  if (std::isfinite(current) && current > 0.0 && delta < -current) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "a reduction by %.4g would take the level %.4g below zero (more than 100 %%): at most -%.4g", -delta,
                  current, current);
    return buf;
  }
  return "";
}

const char* stability_words(const BoundedAnswer& a) {
  if (a.kind == AnswerKind::steady_state) return "stable";
  if (!(a.spectral_radius < 1.0)) return "past a unit root";
  // A horizon answer below 0.95 is given because too many draws do not settle, not because of the estimate.
  return a.spectral_radius >= 0.95 ? "near a unit root" : "not reliably stable";
}

double interval_level_factor(double percent_lower, double percent_upper) {
  const double lo = 1.0 + percent_lower / 100.0, hi = 1.0 + percent_upper / 100.0;
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo <= 0.0) return std::numeric_limits<double>::infinity();
  return hi / lo;
}

std::string effect_unknown_reason(double percent_lower, double percent_upper, double coverage) {
  // "the 90 % interval", or "the interval" when the asker does not know the coverage (causal-ask: the reply
  // carries the bounds, not their level).
  char what[32] = "the interval";
  if (std::isfinite(coverage)) std::snprintf(what, sizeof what, "the %g %% interval", 100.0 * coverage);
  char buf[120];
  if (!std::isfinite(percent_lower) || !std::isfinite(percent_upper)) {
    std::snprintf(buf, sizeof buf, "%s is not finite", what);
    return buf;
  }
  const double factor = interval_level_factor(percent_lower, percent_upper);
  if (!std::isfinite(factor)) {
    std::snprintf(buf, sizeof buf, "%s reaches -100 %%", what);
    return buf;
  }
  if (factor > kMaxKnownLevelFactor) {
    std::snprintf(buf, sizeof buf, "%s spans a factor of %.0f in level", what, factor);
    return buf;
  }
  if (std::max(std::abs(percent_lower), std::abs(percent_upper)) > kPercentDisplayCap) {
    std::snprintf(buf, sizeof buf, "%s reaches beyond %+.0f %%", what,
                  percent_upper > kPercentDisplayCap ? kPercentDisplayCap : -kPercentDisplayCap);
    return buf;
  }
  return "";
}

std::string answer_line(const BoundedAnswer& answer, int channel, double current, const EffectUnits& units) {
  if (!answer.answered()) return "refused: " + answer.reason;
  const auto k = static_cast<Eigen::Index>(channel);
  const double med = percent_of_level(answer.effect.median(k), current, units);
  const double lo = percent_of_level(answer.effect.lower(k), current, units);
  const double hi = percent_of_level(answer.effect.upper(k), current, units);
  auto bare = [](double p) {  // interval ends without the unit, as in "[-12.0, -3.9]"
    std::string s = percent_text(p);
    const auto pos = s.find(" %");
    return pos == std::string::npos ? s : s.substr(0, pos) + s.substr(pos + 2);
  };
  std::string line = answer.kind == AnswerKind::steady_state
                         ? std::string("at steady state")
                         : "after " + std::to_string(answer.horizon_snapshots) + " snapshots";
  char buf[160];
  if (answer.kind != AnswerKind::steady_state && std::isfinite(units.snapshot_hours)) {
    std::snprintf(buf, sizeof buf, " (%.1f h)", answer.horizon_snapshots * units.snapshot_hours);
    line += buf;
  }
  line += ": ";
  std::snprintf(buf, sizeof buf, ", model %s rho=%.3f, %d/%d draws unstable", stability_words(answer),
                answer.spectral_radius, answer.unstable_draws, answer.draws);
  if (const std::string why = effect_unknown_reason(lo, hi, answer.coverage); !why.empty()) {
    return line + "effect unknown (" + why + ")" + buf;
  }
  char cover[32];
  std::snprintf(cover, sizeof cover, " (%g %%)", 100.0 * answer.coverage);
  line += percent_text(med) + " [" + bare(lo) + ", " + bare(hi) + "]" + cover + buf;
  if (!units.log_level && answer.effect.lower(k) < -current) line += " (the level cannot fall below 0: -100 % is the floor)";
  return line;
}

}  // namespace causal::analysis
