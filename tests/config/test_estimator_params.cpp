// causal-estimator's parameter loader (services/causal_estimator/estimator_params.cpp): the shipped file
// loads with the documented values, and every kind of mistake in a copy of it is a ConfigError naming the
// file and the dotted key.
#include "causal/pipeline/estimator_params.hpp"

#include "config_test_util.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using causal::pipeline::load_estimator_health;
using causal::pipeline::load_estimator_output;
using causal::pipeline::load_estimator_params;
using causal::pipeline::FactorMessages;
using causal::test::config_error;
using causal::test::mutated_copy;

const std::string kShipped = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/estimator.yaml";

TEST(EstimatorParams, ShippedFileLoads) {
  const auto p = load_estimator_params(kShipped);
  // Values as written in deploy/config/estimator.yaml (read independently from the file here).
  const YAML::Node doc = YAML::LoadFile(kShipped);
  const YAML::Node s = doc["sample_level"], c = doc["condition_level"];
  EXPECT_EQ(p.sample_level, s["enabled"].as<bool>());
  EXPECT_EQ(p.sample.model.lag_order, s["lag_order"].as<int>());
  EXPECT_EQ(p.sample.model.include_self_lags, s["include_self_lags"].as<bool>());
  EXPECT_EQ(p.sample.noise.automatic, s["noise"]["mode"].as<std::string>() == "automatic");
  EXPECT_DOUBLE_EQ(p.sample.noise.fixed.q, s["noise"]["q"].as<double>());
  EXPECT_DOUBLE_EQ(p.sample.noise.fixed.r, s["noise"]["r"].as<double>());
  EXPECT_DOUBLE_EQ(p.sample.noise.fixed.p0, s["noise"]["p0"].as<double>());
  EXPECT_EQ(p.sample.noise.calibration_samples, s["noise"]["calibration_samples"].as<std::size_t>());
  EXPECT_EQ(p.sample.publish_every, s["publish_every"].as<std::size_t>());
  EXPECT_EQ(p.sample.fixed_lag, s["fixed_lag"].as<int>());

  EXPECT_EQ(p.condition_level, c["enabled"].as<bool>());
  EXPECT_EQ(causal::io::to_string(p.condition.feature), c["feature"].as<std::string>());
  EXPECT_EQ(p.condition.log_transform, c["log_transform"].as<bool>());
  EXPECT_EQ(p.condition.window_samples, c["window_samples"].as<std::size_t>());
  EXPECT_EQ(p.condition.min_samples, c["min_samples"].as<std::size_t>());
  EXPECT_EQ(p.condition_model.model.lag_order, c["lag_order"].as<int>());
  EXPECT_EQ(p.condition_model.model.include_self_lags, c["include_self_lags"].as<bool>());
  EXPECT_EQ(p.condition_model.noise.automatic, c["noise"]["mode"].as<std::string>() == "automatic");
  EXPECT_DOUBLE_EQ(p.condition_model.noise.fixed.q, c["noise"]["q"].as<double>());
  EXPECT_DOUBLE_EQ(p.condition_model.noise.fixed.r, c["noise"]["r"].as<double>());
  EXPECT_EQ(p.condition_model.publish_every, c["publish_every"].as<std::size_t>());
  EXPECT_EQ(p.condition_model.fixed_lag, c["fixed_lag"].as<int>());

  for (const auto& [loaded, node] : {std::pair{p.sample_structure, s["structure"]}, std::pair{p.condition_structure, c["structure"]}}) {
    EXPECT_EQ(loaded.calibration_samples, node["calibration_samples"].as<std::size_t>());
    EXPECT_EQ(loaded.centre, node["centre"].as<bool>());
    EXPECT_EQ(loaded.learn_order, node["causal_order"].as<std::string>() == "lingam");
    EXPECT_DOUBLE_EQ(loaded.prune_threshold, node["prune_threshold"].as<double>());
  }

  EXPECT_DOUBLE_EQ(load_estimator_health(kShipped).deadline_s, doc["health"]["deadline_s"].as<double>());
  // (Compared with the file itself, not with copied numbers: the shipped values may be retuned.)
}

TEST(EstimatorParams, ARoundTripThroughTheEmitterStillLoads) {
  // Guards the mutation helper: an unmodified copy must load, so each failure below is due to its mutation.
  const std::string p = mutated_copy(kShipped, "est_copy.yaml", [](YAML::Node&) {});
  EXPECT_NO_THROW(load_estimator_params(p));
}

struct Mutation {
  const char* name;
  void (*apply)(YAML::Node&);
  const char* key;      // dotted key the message must name
  const char* problem;  // part of the problem description
};

const Mutation kMutations[] = {
    {"missing_publish_every", [](YAML::Node& d) { d["sample_level"].remove("publish_every"); },
     "sample_level.publish_every", "missing"},
    {"typo_publish_evry",
     [](YAML::Node& d) {
       d["sample_level"]["publish_evry"] = d["sample_level"]["publish_every"].as<int>();
       d["sample_level"].remove("publish_every");
     },
     "sample_level.publish_evry", "unknown key"},
    {"q_negative", [](YAML::Node& d) { d["sample_level"]["noise"]["q"] = -1.0; }, "sample_level.noise.q", ">= 0"},
    {"condition_q_negative", [](YAML::Node& d) { d["condition_level"]["noise"]["q"] = -1e-4; },
     "condition_level.noise.q", ">= 0"},
    {"r_zero", [](YAML::Node& d) { d["sample_level"]["noise"]["r"] = 0; }, "sample_level.noise.r", "> 0"},
    {"feature_foo", [](YAML::Node& d) { d["condition_level"]["feature"] = "foo"; }, "condition_level.feature",
     "'foo'"},
    {"mode_auto", [](YAML::Node& d) { d["sample_level"]["noise"]["mode"] = "auto"; }, "sample_level.noise.mode",
     "fixed, automatic"},
    {"lag_order_zero", [](YAML::Node& d) { d["condition_level"]["lag_order"] = 0; }, "condition_level.lag_order",
     "got 0"},
    {"publish_every_fraction", [](YAML::Node& d) { d["sample_level"]["publish_every"] = 10.5; },
     "sample_level.publish_every", "whole number"},
    // The sample-level decimation: every sample (1) is the least, 0 or negative would publish nothing or wrap.
    {"publish_every_zero", [](YAML::Node& d) { d["sample_level"]["publish_every"] = 0; },
     "sample_level.publish_every", "got 0"},
    {"publish_every_negative", [](YAML::Node& d) { d["sample_level"]["publish_every"] = -1024; },
     "sample_level.publish_every", "got -1024"},
    {"enabled_not_bool", [](YAML::Node& d) { d["condition_level"]["enabled"] = "sometimes"; },
     "condition_level.enabled", "true or false"},
    {"noise_not_a_section", [](YAML::Node& d) { d["sample_level"]["noise"] = 3; }, "sample_level.noise", "section"},
    {"missing_section", [](YAML::Node& d) { d.remove("condition_level"); }, "condition_level", "missing"},
    {"unknown_top_key", [](YAML::Node& d) { d["sample_levle"] = 1; }, "sample_levle", "unknown key"},
    {"unknown_noise_key", [](YAML::Node& d) { d["sample_level"]["noise"]["qq"] = 1; }, "sample_level.noise.qq",
     "unknown key"},
    {"calibration_zero", [](YAML::Node& d) { d["sample_level"]["noise"]["calibration_samples"] = 0; },
     "sample_level.noise.calibration_samples", "got 0"},
    {"fixed_lag_negative", [](YAML::Node& d) { d["sample_level"]["fixed_lag"] = -1; }, "sample_level.fixed_lag",
     "got -1"},
    {"min_samples_zero", [](YAML::Node& d) { d["condition_level"]["min_samples"] = 0; },
     "condition_level.min_samples", "got 0"},
    {"missing_structure", [](YAML::Node& d) { d["condition_level"].remove("structure"); },
     "condition_level.structure", "missing"},
    {"causal_order_unknown", [](YAML::Node& d) { d["condition_level"]["structure"]["causal_order"] = "pc"; },
     "condition_level.structure.causal_order", "configured, lingam"},
    {"centre_without_window",
     [](YAML::Node& d) {
       d["sample_level"]["structure"]["centre"] = true;
       d["sample_level"]["structure"]["calibration_samples"] = 0;
     },
     "sample_level.structure.calibration_samples", "must be > 0"},
    {"prune_negative", [](YAML::Node& d) { d["condition_level"]["structure"]["prune_threshold"] = -0.5; },
     "condition_level.structure.prune_threshold", ">= 0"},
    {"both_disabled",
     [](YAML::Node& d) {
       d["sample_level"]["enabled"] = false;
       d["condition_level"]["enabled"] = false;
     },
     "sample_level.enabled", "disabled"},
    {"missing_health", [](YAML::Node& d) { d.remove("health"); }, "health", "missing"},
    {"missing_deadline", [](YAML::Node& d) { d["health"].remove("deadline_s"); }, "health.deadline_s", "missing"},
    {"deadline_negative", [](YAML::Node& d) { d["health"]["deadline_s"] = -1; }, "health.deadline_s", ">= 0"},
    {"deadline_too_long", [](YAML::Node& d) { d["health"]["deadline_s"] = 30000000; }, "health.deadline_s",
     "one day"},
    {"unknown_health_key", [](YAML::Node& d) { d["health"]["lease_s"] = 5; }, "health.lease_s", "unknown key"},
    {"factor_messages_unknown", [](YAML::Node& d) { d["output"]["factor_messages"] = "frames"; },
     "output.factor_messages", "one of"},
    {"factor_messages_missing", [](YAML::Node& d) { d["output"].remove("factor_messages"); }, "output.factor_messages",
     "missing"},
    {"unknown_output_key", [](YAML::Node& d) { d["output"]["per_snapshot"] = true; }, "output.per_snapshot",
     "unknown key"},
};

class EstimatorParamsMutation : public ::testing::TestWithParam<Mutation> {};

TEST_P(EstimatorParamsMutation, ThrowsConfigErrorNamingFileAndKey) {
  const Mutation& m = GetParam();
  const std::string path = mutated_copy(kShipped, std::string("est_") + m.name + ".yaml", m.apply);
  // Every loader of the file: the estimator's parameters, its health and its output section.
  const std::string msg = config_error([&] {
    (void)load_estimator_params(path);
    (void)load_estimator_health(path);
    (void)load_estimator_output(path);
  });
  EXPECT_HAS(msg, path + ": ");
  EXPECT_HAS(msg, std::string(": ") + m.key + ":");
  EXPECT_HAS(msg, m.problem);
}

INSTANTIATE_TEST_SUITE_P(Mutations, EstimatorParamsMutation, ::testing::ValuesIn(kMutations),
                         [](const ::testing::TestParamInfo<Mutation>& p) { return std::string(p.param.name); });

TEST(EstimatorParams, OneTimeScaleDisabledIsFine) {
  const std::string p = mutated_copy(kShipped, "est_sample_off.yaml",
                                     [](YAML::Node& d) { d["sample_level"]["enabled"] = false; });
  const auto params = load_estimator_params(p);
  EXPECT_FALSE(params.sample_level);
  EXPECT_TRUE(params.condition_level);
}

TEST(EstimatorParams, EveryFeatureNameIsAccepted) {
  for (const char* f : {"rms", "meanabs", "kurtosis", "peak"}) {
    const std::string p = mutated_copy(kShipped, std::string("est_feature_") + f + ".yaml",
                                       [f](YAML::Node& d) { d["condition_level"]["feature"] = f; });
    EXPECT_EQ(causal::io::to_string(load_estimator_params(p).condition.feature), f);
  }
}

TEST(EstimatorParams, ZeroDeadlineTurnsTheDeadlineOff) {
  const std::string p = mutated_copy(kShipped, "est_deadline_off.yaml", [](YAML::Node& d) { d["health"]["deadline_s"] = 0; });
  EXPECT_EQ(load_estimator_health(p).deadline_s, 0.0);
}

TEST(EstimatorParams, FactorMessagesAsWrittenAndBatchWithoutTheSection) {
  const YAML::Node doc = YAML::LoadFile(kShipped);
  EXPECT_EQ(load_estimator_output(kShipped).factor_messages == FactorMessages::Set,
            doc["output"]["factor_messages"].as<std::string>() == "set");
  for (const char* mode : {"batch", "set"}) {
    const std::string p = mutated_copy(kShipped, std::string("est_factor_messages_") + mode + ".yaml",
                                       [mode](YAML::Node& d) { d["output"]["factor_messages"] = mode; });
    EXPECT_EQ(load_estimator_output(p).factor_messages, std::string(mode) == "set" ? FactorMessages::Set
                                                                                  : FactorMessages::Batch);
    (void)load_estimator_params(p);  // the other loaders take the section
    (void)load_estimator_health(p);
  }
  // A file written before the section existed: one message per batch, as before.
  const std::string old = mutated_copy(kShipped, "est_no_output.yaml", [](YAML::Node& d) { d.remove("output"); });
  EXPECT_EQ(load_estimator_output(old).factor_messages, FactorMessages::Batch);
}

TEST(EstimatorParams, MissingFileIsAConfigError) {
  const std::string p = causal::test::temp_yaml_path("does_not_exist_estimator.yaml");
  EXPECT_HAS(config_error([&] { (void)load_estimator_params(p); }), p);
}

}  // namespace
