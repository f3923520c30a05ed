#include "recommender_params.hpp"

#include "causal/config/yaml_fields.hpp"

#include <stdexcept>

namespace causal::recommender {

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

}  // namespace

RecommenderParams load_recommender_params(const std::string& path) {
  using config::Section;
  const Section root = Section::load_file(path);
  root.only({"condition_level", "sample_level", "recommendations", "health", "prognosis"});
  RecommenderParams r;

  const Section c = root.child("condition_level");
  c.only({"enabled", "warmup_observations", "baseline_observations", "min_baseline_coverage", "baseline_confidence",
          "cusum_k", "target_arl0", "clip_sigma", "cusum_cap_factor", "clear_fraction", "raise_persistence",
          "clear_persistence", "level_window", "feature_enabled", "feature_log_transform", "warning_ratio",
          "critical_ratio", "advisory_ratio", "baseline_tracking_observations", "max_absorbed_ratio", "innovation_enabled", "nis_enabled", "nis_window", "nis_false_alarm_prob",
          "warning_sigma", "critical_sigma", "factor_enabled", "factor_false_alarm_prob", "factor_persistence",
          "onset_tolerance", "explain_top_factors", "confirmation_observations", "gap_multiple", "operating_step_ratio",
          "settle_trend_sigma", "escalation_persistence", "root_cause_margin_z", "root_cause_persistence"});
  r.condition_enabled = c.boolean("enabled");
  alarms::AlarmParams& p = r.condition;
  p.warmup_observations = static_cast<int>(c.integer("warmup_observations", 0, 1000000));
  p.baseline_observations = static_cast<int>(c.integer("baseline_observations", 8, 1000000));
  p.min_baseline_coverage = c.positive("min_baseline_coverage");
  p.baseline_confidence = c.positive("baseline_confidence");
  p.cusum_k = c.positive("cusum_k");
  p.target_arl0 = c.positive("target_arl0");
  p.clip_sigma = c.positive("clip_sigma");
  p.cusum_cap_factor = c.positive("cusum_cap_factor");
  p.clear_fraction = c.positive("clear_fraction");
  p.raise_persistence = static_cast<int>(c.integer("raise_persistence", 1, 1000));
  p.clear_persistence = static_cast<int>(c.integer("clear_persistence", 1, 1000));
  p.level_window = static_cast<int>(c.integer("level_window", 1, 1000));
  p.feature_enabled = c.boolean("feature_enabled");
  p.feature_log_transform = c.boolean("feature_log_transform");
  p.warning_ratio = c.positive("warning_ratio");
  p.critical_ratio = c.positive("critical_ratio");
  p.advisory_ratio = c.positive("advisory_ratio");
  p.baseline_tracking_observations = static_cast<int>(c.integer("baseline_tracking_observations", 0, 100000000));
  p.max_absorbed_ratio = c.positive("max_absorbed_ratio");
  p.innovation_enabled = c.boolean("innovation_enabled");
  p.nis_enabled = c.boolean("nis_enabled");
  p.nis_window = static_cast<int>(c.integer("nis_window", 1, 100000));
  p.nis_false_alarm_prob = c.positive("nis_false_alarm_prob");
  p.warning_sigma = c.positive("warning_sigma");
  p.critical_sigma = c.positive("critical_sigma");
  p.factor_enabled = c.boolean("factor_enabled");
  p.factor_false_alarm_prob = c.positive("factor_false_alarm_prob");
  p.factor_persistence = static_cast<int>(c.integer("factor_persistence", 1, 100000));
  p.onset_tolerance = static_cast<int>(c.integer("onset_tolerance", 0, 100000));
  p.explain_top_factors = static_cast<int>(c.integer("explain_top_factors", 0, 1000));
  p.confirmation_observations = static_cast<int>(c.integer("confirmation_observations", 3, 100000));
  p.gap_multiple = c.positive("gap_multiple");
  p.operating_step_ratio = c.positive("operating_step_ratio");
  p.settle_trend_sigma = c.positive("settle_trend_sigma");
  p.escalation_persistence = static_cast<int>(c.integer("escalation_persistence", 1, 100000));
  p.root_cause_margin_z = c.positive("root_cause_margin_z");
  p.root_cause_persistence = static_cast<int>(c.integer("root_cause_persistence", 1, 100000));
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    c.fail("enabled", std::string("inconsistent alarm parameters: ") + e.what());
  }

  const Section s = root.child("sample_level");
  s.only({"enabled", "baseline_publications"});
  r.sample_enabled = s.boolean("enabled");
  r.sample_baseline_publications = static_cast<int>(s.integer("baseline_publications", 3, 1000000));

  const Section a = root.child("recommendations");
  a.only({"enabled", "max_per_alarm", "excess_fraction", "min_excess_percent", "coverage", "draws", "model_log_features",
          "max_stable_radius", "max_unstable_share", "horizon_snapshots", "refuse_unstable_share",
          "min_order_confidence", "reference_confirm_observations"});
  r.advice.enabled = a.boolean("enabled");
  r.advice.max_per_alarm = static_cast<int>(a.integer("max_per_alarm", 1, 64));
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

}  // namespace causal::recommender
