// alarms.yaml (alarm-recommender's parameters, also read by causal-alarm-eval and causal-prognosis-eval): one plain
// struct and one loader that rejects missing or invalid keys. The loaders are target causal_advice_params (YAML
// through causal_config), so causal_advice itself stays Eigen + std.
#pragma once

#include "causal/advice/action_catalogue.hpp"
#include "causal/advice/advice_policy.hpp"
#include "causal/advice/advisor.hpp"

#include "causal/alarms/alarm_params.hpp"
#include "causal/prognosis/time_to_level.hpp"

#include <string>

namespace causal::advice {

struct RecommenderParams {
  bool condition_enabled = true;
  alarms::AlarmParams condition;
  bool sample_enabled = true;
  int sample_baseline_publications = 50;
  AdvisorParams advice;
  PolicyParams policy;      // recommendations.min_order_confidence (the interval rule is analysis's constant)
  ActionCatalogue actions = ActionCatalogue::rolling_bearing_defaults();  // actions.yaml (main loads it)
  // health.deadline_s: how long an asset group's causal factors may stay silent while the estimator is alive
  // before a HEALTH alarm is raised (0 = no deadline; a lost estimator still raises one).
  double health_deadline_s = 30.0;
  // prognosis.*: time to the warning / critical / end-of-life level for channels with an open degradation
  // alarm (causal_prognosis), published on causal_twin/prognosis and in the Alarm decision fields.
  bool prognosis_enabled = true;
  prognosis::PrognosisParams prognosis;
};

// Throws causal::config::ConfigError naming the file and key (also for values AlarmParams::validate refuses).
RecommenderParams load_recommender_params(const std::string& path);

// actions.yaml. Throws causal::config::ConfigError naming the file and key.
ActionCatalogue load_action_catalogue(const std::string& path);

}  // namespace causal::advice
