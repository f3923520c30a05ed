// alarm-recommender's parameter loader (services/alarm_recommender/recommender_params.cpp): the shipped file
// loads, and mistakes in a copy are ConfigErrors naming the file and the key.
#include "causal/advice/recommender_params.hpp"

#include "config_test_util.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using causal::advice::load_recommender_params;
using causal::test::config_error;
using causal::test::mutated_copy;

const std::string kShipped = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/alarms.yaml";

TEST(RecommenderParams, ShippedFileLoads) {
  const auto r = load_recommender_params(kShipped);
  const YAML::Node doc = YAML::LoadFile(kShipped);
  const YAML::Node c = doc["condition_level"], s = doc["sample_level"];
  EXPECT_EQ(r.condition_enabled, c["enabled"].as<bool>());
  const auto& p = r.condition;
  EXPECT_EQ(p.warmup_observations, c["warmup_observations"].as<int>());
  EXPECT_EQ(p.baseline_observations, c["baseline_observations"].as<int>());
  EXPECT_DOUBLE_EQ(p.min_baseline_coverage, c["min_baseline_coverage"].as<double>());
  EXPECT_DOUBLE_EQ(p.baseline_confidence, c["baseline_confidence"].as<double>());
  EXPECT_DOUBLE_EQ(p.cusum_k, c["cusum_k"].as<double>());
  EXPECT_DOUBLE_EQ(p.target_arl0, c["target_arl0"].as<double>());
  EXPECT_DOUBLE_EQ(p.clip_sigma, c["clip_sigma"].as<double>());
  EXPECT_DOUBLE_EQ(p.cusum_cap_factor, c["cusum_cap_factor"].as<double>());
  EXPECT_DOUBLE_EQ(p.clear_fraction, c["clear_fraction"].as<double>());
  EXPECT_EQ(p.raise_persistence, c["raise_persistence"].as<int>());
  EXPECT_EQ(p.clear_persistence, c["clear_persistence"].as<int>());
  EXPECT_EQ(p.level_window, c["level_window"].as<int>());
  EXPECT_EQ(p.feature_enabled, c["feature_enabled"].as<bool>());
  EXPECT_EQ(p.feature_log_transform, c["feature_log_transform"].as<bool>());
  EXPECT_DOUBLE_EQ(p.warning_ratio, c["warning_ratio"].as<double>());
  EXPECT_DOUBLE_EQ(p.critical_ratio, c["critical_ratio"].as<double>());
  EXPECT_EQ(p.innovation_enabled, c["innovation_enabled"].as<bool>());
  EXPECT_EQ(p.nis_enabled, c["nis_enabled"].as<bool>());
  EXPECT_EQ(p.nis_window, c["nis_window"].as<int>());
  EXPECT_DOUBLE_EQ(p.nis_false_alarm_prob, c["nis_false_alarm_prob"].as<double>());
  EXPECT_DOUBLE_EQ(p.warning_sigma, c["warning_sigma"].as<double>());
  EXPECT_DOUBLE_EQ(p.critical_sigma, c["critical_sigma"].as<double>());
  EXPECT_EQ(p.factor_enabled, c["factor_enabled"].as<bool>());
  EXPECT_DOUBLE_EQ(p.factor_false_alarm_prob, c["factor_false_alarm_prob"].as<double>());
  EXPECT_EQ(p.factor_persistence, c["factor_persistence"].as<int>());
  EXPECT_EQ(p.onset_tolerance, c["onset_tolerance"].as<int>());
  EXPECT_EQ(p.explain_top_factors, c["explain_top_factors"].as<int>());
  EXPECT_EQ(p.confirmation_observations, c["confirmation_observations"].as<int>());
  EXPECT_DOUBLE_EQ(p.gap_multiple, c["gap_multiple"].as<double>());
  EXPECT_DOUBLE_EQ(p.operating_step_ratio, c["operating_step_ratio"].as<double>());
  EXPECT_DOUBLE_EQ(p.settle_trend_sigma, c["settle_trend_sigma"].as<double>());
  EXPECT_EQ(p.escalation_persistence, c["escalation_persistence"].as<int>());
  EXPECT_DOUBLE_EQ(p.root_cause_margin_z, c["root_cause_margin_z"].as<double>());
  EXPECT_EQ(p.root_cause_persistence, c["root_cause_persistence"].as<int>());
  EXPECT_EQ(r.sample_enabled, s["enabled"].as<bool>());
  EXPECT_EQ(r.sample_baseline_publications, s["baseline_publications"].as<int>());
  EXPECT_NO_THROW(p.validate());
  const YAML::Node a = doc["recommendations"];
  EXPECT_EQ(r.advice.enabled, a["enabled"].as<bool>());
  EXPECT_EQ(r.advice.max_per_alarm, a["max_per_alarm"].as<int>());
  EXPECT_EQ(r.advice.max_candidates, a["max_candidates"].as<int>());
  EXPECT_DOUBLE_EQ(r.advice.excess_fraction, a["excess_fraction"].as<double>());
  EXPECT_DOUBLE_EQ(r.advice.min_excess_percent, a["min_excess_percent"].as<double>());
  EXPECT_DOUBLE_EQ(r.advice.coverage, a["coverage"].as<double>());
  EXPECT_EQ(r.advice.draws, a["draws"].as<int>());
  EXPECT_EQ(r.advice.model_log_features, a["model_log_features"].as<bool>());
  EXPECT_DOUBLE_EQ(r.advice.rule.max_stable_radius, a["max_stable_radius"].as<double>());
  EXPECT_DOUBLE_EQ(r.advice.rule.max_unstable_share, a["max_unstable_share"].as<double>());
  EXPECT_EQ(r.advice.rule.horizon_snapshots, a["horizon_snapshots"].as<int>());
  EXPECT_DOUBLE_EQ(r.advice.rule.refuse_unstable_share, a["refuse_unstable_share"].as<double>());
  EXPECT_DOUBLE_EQ(r.policy.min_order_confidence, a["min_order_confidence"].as<double>());
  EXPECT_DOUBLE_EQ(r.health_deadline_s, doc["health"]["deadline_s"].as<double>());
}

// The advisor must model what the estimator models: the two shipped files agree.
TEST(RecommenderParams, ShippedAdviceMatchesTheShippedEstimator) {
  const auto r = load_recommender_params(kShipped);
  const YAML::Node est = YAML::LoadFile(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/estimator.yaml");
  EXPECT_EQ(r.advice.model_log_features, est["condition_level"]["log_transform"].as<bool>());
}

TEST(RecommenderParams, UnmodifiedCopyLoads) {
  const std::string p = mutated_copy(kShipped, "rec_copy.yaml", [](YAML::Node&) {});
  EXPECT_NO_THROW(load_recommender_params(p));
}

struct Mutation {
  const char* name;
  void (*apply)(YAML::Node&);
  const char* key;      // the message must contain this (dotted key, or the parameter named by validate())
  const char* problem;
};

const Mutation kMutations[] = {
    {"order_confidence_above_one", [](YAML::Node& d) { d["recommendations"]["min_order_confidence"] = 1.5; },
     "recommendations.min_order_confidence", "must be in [0, 1]"},
    {"missing_order_confidence", [](YAML::Node& d) { d["recommendations"].remove("min_order_confidence"); },
     "recommendations.min_order_confidence", "missing"},
    {"missing_cusum_k", [](YAML::Node& d) { d["condition_level"].remove("cusum_k"); }, "condition_level.cusum_k",
     "missing"},
    {"typo_key",
     [](YAML::Node& d) {
       d["condition_level"]["nis_windw"] = 12;
       d["condition_level"].remove("nis_window");
     },
     "condition_level.nis_windw", "unknown key"},
    {"cusum_k_negative", [](YAML::Node& d) { d["condition_level"]["cusum_k"] = -1.5; }, "condition_level.cusum_k",
     "> 0"},
    {"nis_window_zero", [](YAML::Node& d) { d["condition_level"]["nis_window"] = 0; }, "condition_level.nis_window",
     "got 0"},
    {"raise_persistence_text", [](YAML::Node& d) { d["condition_level"]["raise_persistence"] = "one"; },
     "condition_level.raise_persistence", "whole number"},
    {"feature_enabled_not_bool", [](YAML::Node& d) { d["condition_level"]["feature_enabled"] = 2; },
     "condition_level.feature_enabled", "true or false"},
    {"baseline_publications_too_small", [](YAML::Node& d) { d["sample_level"]["baseline_publications"] = 2; },
     "sample_level.baseline_publications", "got 2"},
    {"sample_unknown_key", [](YAML::Node& d) { d["sample_level"]["baseline"] = 3; }, "sample_level.baseline",
     "unknown key"},
    {"missing_sample_section", [](YAML::Node& d) { d.remove("sample_level"); }, "sample_level", "missing"},
    {"missing_recommendations", [](YAML::Node& d) { d.remove("recommendations"); }, ": recommendations:", "missing"},
    {"min_excess_negative", [](YAML::Node& d) { d["recommendations"]["min_excess_percent"] = -1.0; },
     "recommendations.min_excess_percent", ">= 0"},
    {"excess_fraction_above_one", [](YAML::Node& d) { d["recommendations"]["excess_fraction"] = 1.5; },
     "recommendations.excess_fraction", "(0, 1]"},
    {"coverage_one", [](YAML::Node& d) { d["recommendations"]["coverage"] = 1.0; }, "recommendations.coverage",
     "(0, 1)"},
    {"coverage_zero", [](YAML::Node& d) { d["recommendations"]["coverage"] = 0.0; }, "recommendations.coverage",
     "> 0"},
    {"draws_too_few", [](YAML::Node& d) { d["recommendations"]["draws"] = 5; }, "recommendations.draws", "got 5"},
    {"max_per_alarm_zero", [](YAML::Node& d) { d["recommendations"]["max_per_alarm"] = 0; },
     "recommendations.max_per_alarm", "got 0"},
    {"stable_radius_one", [](YAML::Node& d) { d["recommendations"]["max_stable_radius"] = 1.0; },
     "recommendations.max_stable_radius", "(0, 1)"},
    {"horizon_zero", [](YAML::Node& d) { d["recommendations"]["horizon_snapshots"] = 0; },
     "recommendations.horizon_snapshots", "got 0"},
    {"missing_horizon", [](YAML::Node& d) { d["recommendations"].remove("horizon_snapshots"); },
     "recommendations.horizon_snapshots", "missing"},
    {"recommendations_typo", [](YAML::Node& d) { d["recommendations"]["draw"] = 100; }, "recommendations.draw",
     "unknown key"},
    // Values each field accepts on its own but AlarmParams::validate refuses: the message must still name
    // the parameter concerned.
    {"warning_above_critical", [](YAML::Node& d) { d["condition_level"]["warning_ratio"] = 8.0; }, "warning_ratio",
     "inconsistent"},
    {"coverage_above_one", [](YAML::Node& d) { d["condition_level"]["min_baseline_coverage"] = 1.5; },
     "min_baseline_coverage", "inconsistent"},
    {"baseline_too_short", [](YAML::Node& d) { d["condition_level"]["baseline_observations"] = 5; },
     "baseline_observations", "must be in 8.."},
    {"probability_above_half", [](YAML::Node& d) { d["condition_level"]["nis_false_alarm_prob"] = 0.7; },
     "nis_false_alarm_prob", "inconsistent"},
    {"missing_health", [](YAML::Node& d) { d.remove("health"); }, "health", "missing"},
    {"deadline_negative", [](YAML::Node& d) { d["health"]["deadline_s"] = -5; }, "health.deadline_s", ">= 0"},
    {"deadline_too_long", [](YAML::Node& d) { d["health"]["deadline_s"] = 1e9; }, "health.deadline_s", "one day"},
    {"unknown_health_key", [](YAML::Node& d) { d["health"]["deadlin_s"] = 5; }, "health.deadlin_s", "unknown key"},
};

class RecommenderParamsMutation : public ::testing::TestWithParam<Mutation> {};

TEST_P(RecommenderParamsMutation, ThrowsConfigErrorNamingFileAndKey) {
  const Mutation& m = GetParam();
  const std::string path = mutated_copy(kShipped, std::string("rec_") + m.name + ".yaml", m.apply);
  const std::string msg = config_error([&] { load_recommender_params(path); });
  EXPECT_HAS(msg, path + ": ");
  EXPECT_HAS(msg, m.key);
  EXPECT_HAS(msg, m.problem);
}

INSTANTIATE_TEST_SUITE_P(Mutations, RecommenderParamsMutation, ::testing::ValuesIn(kMutations),
                         [](const ::testing::TestParamInfo<Mutation>& p) { return std::string(p.param.name); });

TEST(RecommenderParams, ValidateFailuresNameTheConditionSection) {
  const std::string path = mutated_copy(kShipped, "rec_validate_section.yaml",
                                        [](YAML::Node& d) { d["condition_level"]["critical_sigma"] = 3.0; });
  const std::string msg = config_error([&] { load_recommender_params(path); });
  EXPECT_HAS(msg, path + ": condition_level.");
  EXPECT_HAS(msg, "critical_sigma");
}

}  // namespace
