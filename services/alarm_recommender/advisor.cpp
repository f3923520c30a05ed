#include "advisor.hpp"

#include "causal/analysis/intervention.hpp"
#include "causal/analysis/structural_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace causal::recommender {

std::optional<SvarLayout> layout_from_names(int channels, int lag_order, const std::vector<std::string>& names) {
  // Masks (a configured causal graph) remove factors: rebuild them from which canonical names are present.
  const std::set<std::string> present(names.begin(), names.end());
  for (bool self_lags : {false, true}) {
    ModelSpec spec;
    spec.channels = channels;
    spec.lag_order = lag_order;
    spec.include_self_lags = self_lags;
    try {
      const SvarLayout full(spec);
      const auto g = static_cast<std::size_t>(channels);
      spec.allowed.assign(g, std::vector<bool>(g, false));
      spec.instantaneous_allowed.assign(g, std::vector<bool>(g, false));
      for (int k = 0; k < channels; ++k) {
        for (int i = 0; i < full.factor_count(k); ++i) {
          if (present.count(full.factor_name(k, i)) == 0) continue;
          const Regressor r = full.regressors(k)[static_cast<std::size_t>(i)];
          spec.allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(r.channel)] = true;
          if (r.lag == 0) spec.instantaneous_allowed[static_cast<std::size_t>(k)][static_cast<std::size_t>(r.channel)] = true;
        }
      }
      SvarLayout layout(spec);
      if (layout.factor_names() == names) return layout;
    } catch (const std::invalid_argument&) {
      continue;  // e.g. a spec without any factor
    }
  }
  return std::nullopt;
}

void Advisor::update(const AssembledObservation& a) {
  if (a.time_scale != causal_twin::CONDITION_LEVEL) return;
  AssetModel& m = models_[a.asset_group];
  if (!m.layout) {
    auto layout = layout_from_names(static_cast<int>(a.channel_names.size()), a.lag_order, a.factor_names);
    if (!layout) return;
    m.layout = std::make_unique<SvarLayout>(*layout);
    m.channel_names = a.channel_names;
  }
  m.factors = a.observation.factors;
  m.factor_std = a.observation.factor_std;
  m.blocks = a.covariance_blocks;  // the latest observation decides: no stale blocks with new factors
  if (a.observation.features.size() > 0) m.features = a.observation.features;
}

bool Advisor::blocks_usable(const AssetModel& m) {
  if (!m.layout || m.blocks.empty()) return false;
  for (const auto& b : m.blocks) {
    if (!b.allFinite()) return false;  // a NaN block would poison every Monte Carlo draw
  }
  try {
    analysis::validate_posterior(*m.layout, analysis::FactorPosterior{m.factors, m.blocks});
  } catch (const std::invalid_argument&) {
    return false;  // block sizes do not match the layout rebuilt from the names
  }
  return true;
}

bool Advisor::full_covariance(const std::string& asset_group) const {
  const auto it = models_.find(asset_group);
  return it != models_.end() && blocks_usable(it->second);
}

analysis::FactorPosterior Advisor::posterior(const AssetModel& m) const {
  if (blocks_usable(m)) return analysis::FactorPosterior{m.factors, m.blocks};
  return analysis::posterior_from_std_devs(*m.layout, m.factors, m.factor_std);
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

std::vector<AdviceItem> Advisor::advise(const std::string& asset_group, int target,
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
  analysis::RecommendationOptions options;
  options.uncertainty.coverage = params_.coverage;
  options.uncertainty.draws = params_.draws;
  options.channel_names = m.channel_names;
  options.unit = params_.model_log_features ? "log-level" : "";
  const auto ranked = analysis::rank_interventions(*m.layout, posterior(m), target, candidates, options);
  std::vector<AdviceItem> out;
  for (const auto& r : ranked) {
    if (static_cast<int>(out.size()) >= params_.max_per_alarm) break;
    if (r.status != analysis::AnalysisStatus::ok) continue;
    AdviceItem a;
    a.rank = static_cast<int>(out.size()) + 1;
    a.target = target;
    a.intervene = r.action.channel;
    a.delta = r.action.delta;
    a.immediate = r.immediate;
    a.steady_state = r.steady_state;
    a.lower = r.lower;
    a.upper = r.upper;
    a.coverage = r.coverage;
    const auto& names = m.channel_names;
    a.text = "Reduce " + names[static_cast<std::size_t>(a.intervene)] + " by " + reduction(a.delta) +
             " (back to its baseline): " + names[static_cast<std::size_t>(target)] + " is predicted to change by " +
             percent(a.steady_state) + " at steady state (" + std::to_string(static_cast<int>(a.coverage * 100)) +
             "% interval " + percent(a.lower) + " .. " + percent(a.upper) + "), " + percent(a.immediate) +
             " at once. [" + r.text + "]";
    out.push_back(std::move(a));
  }
  if (out.empty()) why = "no candidate intervention has a stable, identifiable prediction";
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
  const int g = m.layout->channels();
  if (channel < 0 || channel >= g) {
    ans.error = "channel " + std::to_string(channel + 1) + " is outside 1.." + std::to_string(g);
    return ans;
  }
  if (!std::isfinite(delta)) {
    ans.error = "delta must be finite";
    return ans;
  }
  analysis::InterventionQuery q;
  q.channel = channel;
  q.delta = delta;
  q.kind = sustained ? analysis::InterventionKind::sustained : analysis::InterventionKind::impulse;
  analysis::UncertaintyOptions u;
  u.coverage = params_.coverage;
  u.draws = params_.draws;
  const auto eff = analysis::predict_intervention_with_uncertainty(*m.layout, posterior(m), q, u);
  if (eff.point.status != analysis::AnalysisStatus::ok) {
    ans.error = std::string(analysis::to_string(eff.point.status)) + ": " + eff.point.message;
    return ans;
  }
  ans.ok = true;
  ans.immediate = eff.point.immediate;
  ans.steady_state = sustained ? eff.point.steady_state : eff.point.cumulative;
  const auto& iv = sustained ? eff.steady_state : eff.cumulative;
  ans.lower = eff.interval_valid ? iv.lower : Eigen::VectorXd::Constant(g, NAN);
  ans.upper = eff.interval_valid ? iv.upper : Eigen::VectorXd::Constant(g, NAN);
  ans.text = std::string(sustained ? "Sustained " : "One-snapshot ") + "change of " +
             m.channel_names[static_cast<std::size_t>(channel)] + " by " + percent(delta) + ":";
  for (int k = 0; k < g; ++k) {
    if (k == channel) continue;
    ans.text += " " + m.channel_names[static_cast<std::size_t>(k)] + " " + percent(ans.immediate[k]) + " at once, " +
                percent(ans.steady_state[k]) + (sustained ? " at steady state" : " in total") + ";";
  }
  return ans;
}

}  // namespace causal::recommender
