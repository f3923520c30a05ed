#include "causal/advice/advisor.hpp"

#include "causal/analysis/bounded_answer.hpp"
#include "causal/analysis/effect_units.hpp"
#include "causal/analysis/intervention.hpp"
#include "causal/analysis/structural_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace causal::advice {

std::optional<estimation::SvarLayout> layout_from_names(int channels, int lag_order, const std::vector<std::string>& names) {
  // Masks (a configured causal graph) remove factors: rebuild them from which canonical names are present.
  const std::set<std::string> present(names.begin(), names.end());
  for (bool self_lags : {false, true}) {
    estimation::ModelSpec spec;
    spec.channels = channels;
    spec.lag_order = lag_order;
    spec.include_self_lags = self_lags;
    try {
      const estimation::SvarLayout full(spec);
      const auto g = static_cast<std::size_t>(channels);
      spec.allowed.assign(g, std::vector<bool>(g, false));
      spec.instantaneous_allowed.assign(g, std::vector<bool>(g, false));
      for (int k = 0; k < channels; ++k) {
        for (int i = 0; i < full.factor_count(k); ++i) {
          if (present.count(full.factor_name(k, i)) == 0) continue;
          const estimation::Regressor r = full.regressors(k)[static_cast<std::size_t>(i)];
          spec.allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(r.channel)] = true;
          if (r.lag == 0) spec.instantaneous_allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(r.channel)] = true;
        }
      }
      estimation::SvarLayout layout(spec);
      if (layout.factor_names() == names) return layout;
    } catch (const std::invalid_argument&) {
      continue;  // e.g. a spec without any factor
    }
  }
  return std::nullopt;
}

void Advisor::update(const ModelObservation& a) {
  AssetModel& m = models_[a.asset_group];
  if (!m.layout) {
    auto layout = layout_from_names(static_cast<int>(a.channel_names.size()), a.lag_order, a.factor_names);
    if (!layout) return;
    m.layout = std::make_unique<estimation::SvarLayout>(*layout);
    m.channel_names = a.channel_names;
  }
  m.factors = a.observation.factors;
  m.factor_std = a.observation.factor_std;
  m.blocks = a.covariance_blocks;  // the latest observation decides: no stale blocks with new factors
  if (a.observation.features.size() > 0) m.features = a.observation.features;
  const std::int64_t t = a.observation.time_ns;
  if (m.last_time_ns != 0 && t > m.last_time_ns) {
    m.spacings_h.push_back(static_cast<double>(t - m.last_time_ns) / 3.6e12);
    if (m.spacings_h.size() > 31) m.spacings_h.erase(m.spacings_h.begin());
  }
  if (t != 0) m.last_time_ns = t;
  ++m.observations;
  note_reference(m, params_.reference_confirm_observations);
}

Advisor::FactorSnapshot Advisor::snapshot_of(const AssetModel& m) {
  return FactorSnapshot{m.factors, m.factor_std, m.blocks, m.observations};
}

void Advisor::note_reference(AssetModel& m, int confirm) {
  if (m.candidate && m.observations - m.candidate->at >= static_cast<std::uint64_t>(std::max(confirm, 0))) {
    m.reference = std::move(m.candidate);
    m.candidate.reset();
  }
  if (!m.candidate && m.settled) m.candidate = snapshot_of(m);
}

void Advisor::set_health(const std::string& asset_group, bool learning, bool degraded) {
  const auto it = models_.find(asset_group);
  if (it == models_.end()) return;
  it->second.settled = !learning && !degraded;
  // A candidate captured shortly before the alarm may already carry the fault: it never becomes the reference.
  if (!it->second.settled) it->second.candidate.reset();
}

double Advisor::snapshot_hours(const std::string& asset_group) const {
  const auto it = models_.find(asset_group);
  if (it == models_.end() || it->second.spacings_h.empty()) return NAN;
  // The median: a gap in the run (hours or days) must not stretch the cadence.
  std::vector<double> s = it->second.spacings_h;
  std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2), s.end());
  return s[s.size() / 2];
}

namespace {

bool blocks_fit(const estimation::SvarLayout& layout, const Eigen::VectorXd& factors, const std::vector<Eigen::MatrixXd>& blocks) {
  if (blocks.empty()) return false;
  for (const auto& b : blocks) {
    if (!b.allFinite()) return false;  // a NaN block would poison every Monte Carlo draw
  }
  try {
    analysis::validate_posterior(layout, analysis::FactorPosterior{factors, blocks});
  } catch (const std::invalid_argument&) {
    return false;  // block sizes do not match the layout rebuilt from the names
  }
  return true;
}

}  // namespace

bool Advisor::blocks_usable(const AssetModel& m) { return m.layout && blocks_fit(*m.layout, m.factors, m.blocks); }

bool Advisor::full_covariance(const std::string& asset_group) const {
  const auto it = models_.find(asset_group);
  return it != models_.end() && blocks_usable(it->second);
}

analysis::FactorPosterior Advisor::posterior(const AssetModel& m) const {
  if (blocks_usable(m)) return analysis::FactorPosterior{m.factors, m.blocks};
  return analysis::posterior_from_std_devs(*m.layout, m.factors, m.factor_std);
}

analysis::FactorPosterior Advisor::posterior(const estimation::SvarLayout& layout, const FactorSnapshot& s) const {
  if (blocks_fit(layout, s.factors, s.blocks)) return analysis::FactorPosterior{s.factors, s.blocks};
  return analysis::posterior_from_std_devs(layout, s.factors, s.factor_std);
}

void Advisor::compare_with_reference(const AssetModel& m, int target,
                                     const std::vector<analysis::CandidateIntervention>& candidates,
                                     const analysis::RecommendationOptions& options, double level,
                                     std::vector<AdviceItem>& items) const {
  if (!m.reference || m.reference->factors.size() != m.factors.size()) return;
  // The same questions on the model as it was while healthy: a lever must have been a lever before the fault.
  const auto before = analysis::rank_interventions(*m.layout, posterior(*m.layout, *m.reference), target, candidates, options);
  const analysis::EffectUnits u = units(&m);
  for (auto& item : items) {
    for (const auto& r : before) {
      if (r.action.channel != item.intervene) continue;
      // Held: the healthy model gives the same effect, reliably, or at least half of it with the same sign
      // (an early reference is uncertain: its 12-snapshot interval can be wide near a unit root even where
      // the link is strong). On the simulated plants the healthy medians are -42..-52 % with a lever and
      // -9..+12 % without one (causal_bench_lever_decisions, VERBOSE=1).
      const bool finite = std::isfinite(r.effect) && std::isfinite(item.effect);
      const bool held = finite && (r.effect > 0.0) == (item.effect > 0.0) &&
                        (r.reliable || std::abs(r.effect) >= 0.5 * std::abs(item.effect));
      item.reference = held ? "held" : "appeared";
      item.reference_percent = analysis::percent_of_level(r.effect, level, u);
    }
  }
}

Eigen::VectorXd Advisor::to_model_units(const Eigen::VectorXd& features) const {
  if (!params_.model_log_features) return features;
  Eigen::VectorXd out(features.size());
  for (Eigen::Index i = 0; i < features.size(); ++i) out[i] = features[i] > 0 ? std::log(features[i]) : NAN;
  return out;
}

std::string Advisor::percent(double model_delta) const {
  char buf[64];
  if (params_.model_log_features) {
    std::snprintf(buf, sizeof buf, "%+.1f %%", 100.0 * std::expm1(model_delta));
  } else {
    std::snprintf(buf, sizeof buf, "%+.4g", model_delta);
  }
  return buf;
}

std::string Advisor::reduction(double model_delta) const {
  char buf[64];
  if (params_.model_log_features) {
    std::snprintf(buf, sizeof buf, "%.1f %%", -100.0 * std::expm1(model_delta));
  } else {
    std::snprintf(buf, sizeof buf, "%.4g", -model_delta);
  }
  return buf;
}

analysis::EffectUnits Advisor::units(const AssetModel* m) const {
  analysis::EffectUnits u;
  u.log_level = params_.model_log_features;
  if (m != nullptr && !m->spacings_h.empty()) {
    std::vector<double> s = m->spacings_h;
    std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2), s.end());
    u.snapshot_hours = s[s.size() / 2];
  }
  return u;
}

analysis::UncertaintyOptions Advisor::uncertainty() const {
  analysis::UncertaintyOptions u;
  u.coverage = params_.coverage;
  u.draws = params_.draws;
  return u;
}

namespace {

AnswerDiagnostics diagnostics(const analysis::BoundedAnswer& a) {
  AnswerDiagnostics d;
  d.kind = analysis::to_string(a.kind);
  d.horizon_snapshots = a.horizon_snapshots;
  d.spectral_radius = a.spectral_radius;
  d.draws = a.draws;
  d.unstable_draws = a.unstable_draws;
  d.unstable_share = a.unstable_share();
  return d;
}

}  // namespace

std::vector<AdviceItem> Advisor::advise(const std::string& asset_group, int target,
                                        const Eigen::VectorXd& baseline_features, std::string& why) const {
  std::vector<AdviceItem> all = evaluate(asset_group, target, baseline_features, why);
  std::vector<AdviceItem> out;
  for (auto& a : all) {
    if (static_cast<int>(out.size()) >= params_.max_per_alarm || !a.reliable) break;  // reliable ones come first
    out.push_back(std::move(a));
  }
  // Honest negative advice: the best candidate, said to be no reliable lever (never "as if it helped").
  if (out.empty() && !all.empty()) out.push_back(std::move(all.front()));
  return out;
}

std::vector<AdviceItem> Advisor::evaluate(const std::string& asset_group, int target,
                                          const Eigen::VectorXd& baseline_features, std::string& why) const {
  const auto it = models_.find(asset_group);
  if (it == models_.end() || !it->second.layout) {
    why = "no condition-level causal model for this asset group yet";
    return {};
  }
  const AssetModel& m = it->second;
  if (m.features.size() == 0 || baseline_features.size() != m.features.size()) {
    why = "no current condition features to compare with the baseline";
    return {};
  }
  const Eigen::VectorXd current = to_model_units(m.features);
  const Eigen::VectorXd baseline = to_model_units(baseline_features);
  if (!current.allFinite() || !baseline.allFinite()) {
    why = "a condition feature or its baseline is not positive/finite";
    return {};
  }
  auto candidates = analysis::candidates_from_excess(current, baseline, target, params_.excess_fraction);
  // A channel barely above its baseline is within its normal spread: acting on it is no advice.
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const analysis::CandidateIntervention& c) {
                                    const auto j = static_cast<Eigen::Index>(c.channel);
                                    return m.features[j] < baseline_features[j] * (1.0 + params_.min_excess_percent / 100.0);
                                  }),
                   candidates.end());
  if (candidates.empty()) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "no other channel is %.3g %% or more above its baseline: nothing upstream to act on",
                  params_.min_excess_percent);
    why = buf;
    return {};
  }
  // Each candidate costs `draws` Monte Carlo solves of the G-channel model: only the max_candidates with the
  // largest excess over their baseline are evaluated (AdvisorParams::max_candidates).
  if (candidates.size() > static_cast<std::size_t>(params_.max_candidates)) {
    std::stable_sort(candidates.begin(), candidates.end(), [](const analysis::CandidateIntervention& a,
                                                              const analysis::CandidateIntervention& b) {
      return std::abs(a.delta) > std::abs(b.delta);
    });
    candidates.resize(static_cast<std::size_t>(params_.max_candidates));
  }
  analysis::RecommendationOptions options;
  options.uncertainty = uncertainty();
  options.channel_names = m.channel_names;
  options.unit = params_.model_log_features ? "log-level" : "";
  options.rule = params_.rule;
  options.draw_sharing = params_.draw_sharing;
  const auto ranked = analysis::rank_interventions(*m.layout, posterior(m), target, candidates, options);
  const auto& names = m.channel_names;
  const double level = m.features[target];
  const analysis::EffectUnits u = units(&m);
  auto item_from = [&](const analysis::Recommendation& r) {
    AdviceItem a;
    a.target = target;
    a.intervene = r.action.channel;
    a.delta = r.action.delta;
    a.immediate = r.immediate;
    a.steady_state = r.steady_state;
    a.effect = r.effect;
    a.lower = r.lower;
    a.upper = r.upper;
    a.coverage = r.coverage;
    a.percent = analysis::percent_of_level(r.effect, level, u);
    a.percent_lower = analysis::percent_of_level(r.lower, level, u);
    a.percent_upper = analysis::percent_of_level(r.upper, level, u);
    a.level_change = analysis::level_change(r.effect, level, u);
    a.reliable = r.reliable;
    a.diag = diagnostics(r.answer);
    a.summary = analysis::answer_line(r.answer, target, level, u);
    return a;
  };
  std::vector<AdviceItem> out;
  for (const auto& r : ranked) {
    AdviceItem a = item_from(r);
    a.rank = static_cast<int>(out.size()) + 1;
    a.reduction = reduction(a.delta);
    const std::string& lever = names[static_cast<std::size_t>(a.intervene)];
    const std::string& goal = names[static_cast<std::size_t>(target)];
    if (r.reliable) {
      a.text = "Reduce " + lever + " by " + reduction(a.delta) + " (back to its baseline): " + goal + " " + a.summary +
               "; " + analysis::percent_text(analysis::percent_of_level(a.immediate, level, u)) + " at once.";
    } else {
      a.text = "No reliable lever for " + goal + ": reducing " + lever + " by " + reduction(a.delta) +
               " (back to its baseline) gives " + goal + " " + a.summary +
               (r.interval_valid ? "; the interval includes no reduction." : ".");
    }
    out.push_back(std::move(a));
  }
  compare_with_reference(m, target, candidates, options, level, out);
  return out;
}

WhatIfAnswer Advisor::what_if(const std::string& asset_group, int channel, double delta, bool sustained) const {
  WhatIfAnswer ans;
  const auto it = models_.find(asset_group);
  if (it == models_.end() || !it->second.layout) {
    ans.error = "unknown asset group '" + asset_group + "' (no condition-level model yet)";
    return ans;
  }
  const AssetModel& m = it->second;
  ans.channel_names = m.channel_names;
  const int g = m.layout->channels();
  if (channel < 0 || channel >= g) {
    ans.error = "channel " + std::to_string(channel + 1) + " is outside 1.." + std::to_string(g);
    return ans;
  }
  if (!std::isfinite(delta)) {
    ans.error = "delta must be finite";
    return ans;
  }
  const analysis::EffectUnits u = units(&m);
  const Eigen::VectorXd levels = m.features.size() == g ? m.features : Eigen::VectorXd::Constant(g, NAN);
  if (const std::string bad = analysis::impossible_intervention(delta, levels[channel], u); !bad.empty()) {
    ans.error = "impossible intervention on " + m.channel_names[static_cast<std::size_t>(channel)] + ": " + bad;
    return ans;
  }
  analysis::InterventionQuery q;
  q.channel = channel;
  q.delta = delta;
  q.kind = sustained ? analysis::InterventionKind::sustained : analysis::InterventionKind::impulse;
  const auto a = analysis::answer_intervention(*m.layout, posterior(m), q, params_.rule, uncertainty());
  ans.diag = diagnostics(a);
  const std::string what = std::string(sustained ? "Sustained " : "One-snapshot ") + "change of " +
                           m.channel_names[static_cast<std::size_t>(channel)] + " by " + percent(delta);
  if (!a.answered()) {
    ans.error = "refused: " + a.reason;
    ans.summary = analysis::answer_line(a, channel, levels[channel], u);
    ans.text = what + ": " + ans.summary;
    return ans;
  }
  ans.ok = true;
  ans.immediate = a.immediate.median;
  ans.effect = a.effect.median;
  ans.steady_state = a.kind == analysis::AnswerKind::steady_state ? a.effect.median : Eigen::VectorXd::Constant(g, NAN);
  ans.lower = a.effect.lower;
  ans.upper = a.effect.upper;
  ans.percent.resize(g);
  ans.percent_lower.resize(g);
  ans.percent_upper.resize(g);
  for (int k = 0; k < g; ++k) {
    ans.percent[k] = analysis::percent_of_level(a.effect.median[k], levels[k], u);
    ans.percent_lower[k] = analysis::percent_of_level(a.effect.lower[k], levels[k], u);
    ans.percent_upper[k] = analysis::percent_of_level(a.effect.upper[k], levels[k], u);
  }
  // One line: what was asked, the kind of answer with its stability, then every other channel's effect.
  char head[200];
  std::snprintf(head, sizeof head, " (%s%s, %g %% intervals, model %s rho=%.3f, %d/%d draws unstable):",
                a.kind == analysis::AnswerKind::steady_state ? "at steady state"
                                                              : ("after " + std::to_string(a.horizon_snapshots) + " snapshots").c_str(),
                sustained ? "" : ", in total", 100.0 * a.coverage,
                analysis::stability_words(a),
                a.spectral_radius, a.unstable_draws, a.draws);
  ans.summary = head;
  ans.text = what + head;
  for (int k = 0; k < g; ++k) {
    if (k == channel) continue;
    if (const std::string why = analysis::effect_unknown_reason(ans.percent_lower[k], ans.percent_upper[k], a.coverage);
        !why.empty()) {
      ans.text += " " + m.channel_names[static_cast<std::size_t>(k)] + " effect unknown (" + why + ");";
      continue;
    }
    ans.text += " " + m.channel_names[static_cast<std::size_t>(k)] + " " + analysis::percent_text(ans.percent[k]) + " [" +
                analysis::percent_text(ans.percent_lower[k]) + ", " + analysis::percent_text(ans.percent_upper[k]) + "];";
  }
  return ans;
}

}  // namespace causal::advice
