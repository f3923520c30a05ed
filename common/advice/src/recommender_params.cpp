#include "causal/advice/recommender_params.hpp"

#include "causal/config/yaml_fields.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace causal::advice {

namespace {

void load_prognosis(const config::Section& g, RecommenderParams& r) {
  g.only({"enabled", "end_of_life_ratio", "coverage", "min_trend_z", "min_points_since_onset", "max_horizon_hours",
          "max_width_factor", "acceleration_diffusion", "forecast_diffusion", "level_diffusion", "initial_slope_std",
          "initial_acceleration_std", "min_noise_std", "huber_k", "noise_memory", "step_std", "pessimistic_z",
          "calibration_lag_hours", "calibration_memory"});
  r.prognosis_enabled = g.boolean("enabled");
  prognosis::PrognosisParams& p = r.prognosis;
  p.end_of_life_ratio = g.positive("end_of_life_ratio");
  p.coverage = g.positive("coverage");
  p.min_trend_z = g.non_negative("min_trend_z");
  p.min_points_since_onset = static_cast<int>(g.integer("min_points_since_onset", 2, 1000000));
  p.max_horizon_hours = g.positive("max_horizon_hours");
  p.max_width_factor = g.positive("max_width_factor");
  p.pessimistic_z = g.non_negative("pessimistic_z");
  p.trend.acceleration_diffusion = g.non_negative("acceleration_diffusion");
  p.trend.forecast_diffusion = g.non_negative("forecast_diffusion");
  p.trend.level_diffusion = g.non_negative("level_diffusion");
  p.trend.initial_slope_std = g.positive("initial_slope_std");
  p.trend.initial_acceleration_std = g.positive("initial_acceleration_std");
  p.trend.min_noise_std = g.positive("min_noise_std");
  p.trend.huber_k = g.positive("huber_k");
  p.trend.noise_memory = g.positive("noise_memory");
  p.trend.step_std = g.non_negative("step_std");
  p.trend.calibration_lag_hours = g.non_negative("calibration_lag_hours");
  p.trend.calibration_memory = g.positive("calibration_memory");
  if (p.end_of_life_ratio <= r.condition.critical_ratio) {
    g.fail("end_of_life_ratio", "must be above condition_level.critical_ratio (the end of life comes after critical)");
  }
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    g.fail("enabled", std::string("inconsistent prognosis parameters: ") + e.what());
  }
}

// One condition_level key of AlarmParams: a flag, a number > 0, or a whole number in [lo, hi].
using P = alarms::AlarmParams;
struct AlarmKey {
  const char* name;
  bool P::*flag;
  double P::*positive;
  int P::*whole;
  long lo, hi;
};
AlarmKey flag(const char* name, bool P::*m) { return {name, m, nullptr, nullptr, 0, 0}; }
AlarmKey positive(const char* name, double P::*m) { return {name, nullptr, m, nullptr, 0, 0}; }
AlarmKey whole(const char* name, int P::*m, long lo, long hi) { return {name, nullptr, nullptr, m, lo, hi}; }

// Every condition_level key but "enabled", each once: the list of known keys and the reading come from it
// (in this order: the first bad key is the one reported).
const std::vector<AlarmKey>& alarm_keys() {
  static const std::vector<AlarmKey> keys{
      whole("warmup_observations", &P::warmup_observations, 0, 1000000),
      whole("baseline_observations", &P::baseline_observations, 8, 1000000),
      positive("min_baseline_coverage", &P::min_baseline_coverage),
      positive("baseline_confidence", &P::baseline_confidence),
      positive("cusum_k", &P::cusum_k),
      positive("target_arl0", &P::target_arl0),
      positive("clip_sigma", &P::clip_sigma),
      positive("cusum_cap_factor", &P::cusum_cap_factor),
      positive("clear_fraction", &P::clear_fraction),
      whole("raise_persistence", &P::raise_persistence, 1, 1000),
      whole("innovation_persistence", &P::innovation_persistence, 1, 1000),
      whole("clear_persistence", &P::clear_persistence, 1, 1000),
      whole("level_window", &P::level_window, 1, 1000),
      flag("feature_enabled", &P::feature_enabled),
      flag("feature_log_transform", &P::feature_log_transform),
      positive("warning_ratio", &P::warning_ratio),
      positive("critical_ratio", &P::critical_ratio),
      positive("advisory_ratio", &P::advisory_ratio),
      whole("baseline_tracking_observations", &P::baseline_tracking_observations, 0, 100000000),
      whole("healthy_range_observations", &P::healthy_range_observations, 0, 100000000),
      positive("max_absorbed_ratio", &P::max_absorbed_ratio),
      flag("innovation_enabled", &P::innovation_enabled),
      flag("nis_enabled", &P::nis_enabled),
      whole("nis_window", &P::nis_window, 1, 100000),
      positive("nis_false_alarm_prob", &P::nis_false_alarm_prob),
      positive("warning_sigma", &P::warning_sigma),
      positive("critical_sigma", &P::critical_sigma),
      flag("factor_enabled", &P::factor_enabled),
      positive("factor_false_alarm_prob", &P::factor_false_alarm_prob),
      whole("factor_persistence", &P::factor_persistence, 1, 100000),
      whole("onset_tolerance", &P::onset_tolerance, 0, 100000),
      whole("explain_top_factors", &P::explain_top_factors, 0, 1000),
      whole("confirmation_observations", &P::confirmation_observations, 3, 100000),
      positive("gap_multiple", &P::gap_multiple),
      positive("operating_step_ratio", &P::operating_step_ratio),
      positive("settle_trend_sigma", &P::settle_trend_sigma),
      whole("escalation_persistence", &P::escalation_persistence, 1, 100000),
      positive("root_cause_margin_z", &P::root_cause_margin_z),
      whole("root_cause_persistence", &P::root_cause_persistence, 1, 100000),
  };
  return keys;
}

void load_alarm_params(const config::Section& c, bool& enabled, alarms::AlarmParams& p) {
  std::vector<std::string> known{"enabled"};
  for (const AlarmKey& k : alarm_keys()) known.emplace_back(k.name);
  c.only(known);
  enabled = c.boolean("enabled");
  for (const AlarmKey& k : alarm_keys()) {
    if (k.flag != nullptr) p.*k.flag = c.boolean(k.name);
    if (k.positive != nullptr) p.*k.positive = c.positive(k.name);
    if (k.whole != nullptr) p.*k.whole = static_cast<int>(c.integer(k.name, k.lo, k.hi));
  }
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    c.fail("enabled", std::string("inconsistent alarm parameters: ") + e.what());
  }
}

}  // namespace

RecommenderParams load_recommender_params(const std::string& path) {
  using config::Section;
  const Section root = Section::load_file(path);
  root.only({"condition_level", "sample_level", "recommendations", "health", "prognosis"});
  RecommenderParams r;

  load_alarm_params(root.child("condition_level"), r.condition_enabled, r.condition);

  const Section s = root.child("sample_level");
  s.only({"enabled", "baseline_publications"});
  r.sample_enabled = s.boolean("enabled");
  r.sample_baseline_publications = static_cast<int>(s.integer("baseline_publications", 3, 1000000));

  const Section a = root.child("recommendations");
  a.only({"enabled", "max_per_alarm", "max_candidates", "excess_fraction", "min_excess_percent", "coverage", "draws",
          "model_log_features",
          "max_stable_radius", "max_unstable_share", "horizon_snapshots", "refuse_unstable_share",
          "min_order_confidence", "reference_confirm_observations"});
  r.advice.enabled = a.boolean("enabled");
  r.advice.max_per_alarm = static_cast<int>(a.integer("max_per_alarm", 1, 64));
  r.advice.max_candidates = static_cast<int>(a.integer("max_candidates", 1, 64));
  r.advice.excess_fraction = a.positive("excess_fraction");
  if (r.advice.excess_fraction > 1.0) a.fail("excess_fraction", "must be in (0, 1]");
  r.advice.min_excess_percent = a.non_negative("min_excess_percent");
  r.advice.coverage = a.positive("coverage");
  if (r.advice.coverage >= 1.0) a.fail("coverage", "must be in (0, 1)");
  r.advice.draws = static_cast<int>(a.integer("draws", 10, 1000000));
  r.advice.model_log_features = a.boolean("model_log_features");
  r.advice.rule.max_stable_radius = a.positive("max_stable_radius");
  if (r.advice.rule.max_stable_radius >= 1.0) a.fail("max_stable_radius", "must be in (0, 1): a steady state needs rho < 1");
  r.advice.rule.max_unstable_share = a.non_negative("max_unstable_share");
  if (r.advice.rule.max_unstable_share > 1.0) a.fail("max_unstable_share", "must be in [0, 1]");
  r.advice.rule.horizon_snapshots = static_cast<int>(a.integer("horizon_snapshots", 1, 100000));
  r.advice.rule.refuse_unstable_share = a.non_negative("refuse_unstable_share");
  if (r.advice.rule.refuse_unstable_share > 1.0) a.fail("refuse_unstable_share", "must be in [0, 1]");
  r.policy.min_order_confidence = a.non_negative("min_order_confidence");
  if (r.policy.min_order_confidence > 1.0) a.fail("min_order_confidence", "must be in [0, 1]");
  r.advice.reference_confirm_observations = static_cast<int>(a.integer("reference_confirm_observations", 1, 10000000));

  const Section h = root.child("health");
  h.only({"deadline_s"});
  r.health_deadline_s = h.non_negative("deadline_s");
  // A deadline far beyond any plant cadence is a typo (e.g. milliseconds), not a choice: one day at most.
  if (r.health_deadline_s > 86400.0) h.fail("deadline_s", "must be <= 86400 s (one day)");
  load_prognosis(root.child("prognosis"), r);
  return r;
}

}  // namespace causal::advice
