#include "causal/analysis/recommendation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace causal::analysis {
namespace {

std::string fixed(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

// Fixed text of a user-given amount without trailing zeros (0.020 -> "0.02").
std::string amount(double value) {
  std::string s = fixed(value, std::min(decimals_for(value) + 1, 9));
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  return s;
}

std::string with_unit(const std::string& number, const std::string& unit) {
  return unit.empty() ? number : number + " " + unit;
}

std::string channel_name(int c, const std::vector<std::string>& names) {
  if (c >= 0 && c < static_cast<int>(names.size())) return names[static_cast<std::size_t>(c)];
  return "channel " + std::to_string(c + 1);
}

}  // namespace

int decimals_for(double reference) {
  const double a = std::abs(reference);
  if (!(a > 0.0) || !std::isfinite(a)) return 3;
  const int d = 1 - static_cast<int>(std::floor(std::log10(a)));
  return std::clamp(d, 0, 9);
}

std::string describe_recommendation(const Recommendation& rec, int target, const std::vector<std::string>& names,
                                    const std::string& unit) {
  const std::string verb = rec.action.delta < 0.0 ? "Reduce " : "Raise ";
  std::string text = verb + channel_name(rec.action.channel, names) + " by " +
                     with_unit(amount(std::abs(rec.action.delta)), unit) + ": ";
  const std::string target_name = channel_name(target, names);
  if (!rec.answer.answered()) {
    return text + "the effect on " + target_name + " cannot be predicted (" + rec.message + ").";
  }
  // Two significant digits of the effect, and enough to show the interval's width with one digit.
  int dec = decimals_for(std::abs(rec.effect) > 0.0 ? rec.effect : rec.immediate);
  if (rec.interval_valid && rec.upper > rec.lower) {
    dec = std::clamp(std::max(dec, decimals_for(rec.upper - rec.lower) - 1), 0, 9);
  }
  const bool drop_now = rec.immediate < 0.0;
  const double now = std::abs(rec.immediate);
  const bool no_change_now = now < 0.5 * std::pow(10.0, -dec);
  const bool drop = rec.effect < 0.0;
  const double size = std::abs(rec.effect);
  text += target_name + " is predicted to " + (drop ? "drop" : "rise") + " by " + with_unit(fixed(size, dec), unit);
  if (rec.interval_valid) {
    // Interval of the drop (or rise) magnitude, ascending.
    const double lo = drop ? -rec.upper : rec.lower;
    const double hi = drop ? -rec.lower : rec.upper;
    char pct[16];
    std::snprintf(pct, sizeof pct, "%g", 100.0 * rec.coverage);
    text += std::string(" (") + pct + "% interval " + fixed(lo, dec) + ".." + fixed(hi, dec) + ")";
  }
  text += rec.answer.kind == AnswerKind::steady_state
              ? std::string(" at steady state, ")
              : " after " + std::to_string(rec.answer.horizon_snapshots) + " snapshots (no reliable steady state), ";
  if (no_change_now) {
    text += "no change at once";
  } else if (drop_now == drop) {
    text += fixed(now, dec) + " at once";
  } else {
    text += std::string("but ") + (drop_now ? "drop" : "rise") + " by " + fixed(now, dec) + " at once";
  }
  text += ".";
  if (rec.interval_valid && rec.lower <= 0.0 && rec.upper >= 0.0) {
    text += " The interval includes no change: the direction of the effect is uncertain.";
  }
  return text;
}

std::vector<Recommendation> rank_interventions(const estimation::SvarLayout& layout, const FactorPosterior& posterior, int target,
                                               const std::vector<CandidateIntervention>& candidates,
                                               const RecommendationOptions& options) {
  const int g = layout.channels();
  if (target < 0 || target >= g) throw std::invalid_argument("recommendation: target channel outside 0.." + std::to_string(g - 1));
  if (!options.channel_names.empty() && static_cast<int>(options.channel_names.size()) != g) {
    throw std::invalid_argument("recommendation: " + std::to_string(options.channel_names.size()) +
                                " channel names for " + std::to_string(g) + " channels");
  }
  std::vector<InterventionQuery> queries;
  for (const CandidateIntervention& c : candidates) {
    if (c.channel < 0 || c.channel >= g) {
      throw std::invalid_argument("recommendation: candidate channel " + std::to_string(c.channel) + " outside 0.." +
                                  std::to_string(g - 1));
    }
    if (c.channel == target) throw std::invalid_argument("recommendation: a candidate intervenes on the target itself");
    if (!std::isfinite(c.delta)) throw std::invalid_argument("recommendation: non-finite candidate delta");
    InterventionQuery query;
    query.channel = c.channel;
    query.delta = c.delta;
    query.kind = InterventionKind::sustained;
    queries.push_back(query);
  }
  // Every candidate is answered from the same posterior draws (common random numbers): the ranking compares
  // them on equal terms, and each draw is sampled and checked for settling once, not once per candidate.
  std::vector<BoundedAnswer> answers =
      answer_interventions(layout, posterior, queries, options.rule, options.uncertainty, options.draw_sharing);
  std::vector<Recommendation> out;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    Recommendation rec;
    rec.action = candidates[i];
    rec.answer = std::move(answers[i]);
    rec.status = rec.answer.status;
    rec.message = rec.answer.reason;
    rec.immediate = rec.answer.immediate.median(target);
    rec.effect = rec.answer.effect.median(target);
    rec.steady_state = rec.answer.kind == AnswerKind::steady_state ? rec.effect : std::nan("");
    rec.lower = rec.answer.effect.lower(target);
    rec.upper = rec.answer.effect.upper(target);
    rec.interval_valid = rec.answer.answered();
    rec.reliable = rec.interval_valid && rec.upper < 0.0;
    rec.coverage = rec.answer.coverage;
    rec.text = describe_recommendation(rec, target, options.channel_names, options.unit);
    out.push_back(std::move(rec));
  }
  // 0 reliable, 1 answered but unreliable, 2 refused.
  const auto tier = [](const Recommendation& r) { return r.reliable ? 0 : r.interval_valid ? 1 : 2; };
  std::stable_sort(out.begin(), out.end(), [&](const Recommendation& a, const Recommendation& b) {
    if (tier(a) != tier(b)) return tier(a) < tier(b);
    if (tier(a) < 2 && a.upper != b.upper) return a.upper < b.upper;
    return a.action.channel < b.action.channel;
  });
  return out;
}

std::vector<CandidateIntervention> candidates_from_excess(const Eigen::VectorXd& current, const Eigen::VectorXd& baseline,
                                                          int target, double fraction) {
  if (current.size() != baseline.size()) throw std::invalid_argument("candidates: current and baseline sizes differ");
  if (target < 0 || target >= current.size()) throw std::invalid_argument("candidates: target channel out of range");
  if (!(fraction > 0.0 && fraction <= 1.0)) throw std::invalid_argument("candidates: fraction must be in (0, 1]");
  std::vector<CandidateIntervention> out;
  for (Eigen::Index j = 0; j < current.size(); ++j) {
    if (j == target) continue;
    const double excess = current(j) - baseline(j);
    if (std::isfinite(excess) && excess > 0.0) out.push_back({static_cast<int>(j), -fraction * excess});
  }
  return out;
}

}  // namespace causal::analysis
