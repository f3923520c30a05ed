#include "causal/pipeline/estimator_params.hpp"

#include "causal/config/yaml_fields.hpp"

namespace causal::pipeline {

namespace {

using config::Section;

pipeline::NoiseSetting load_noise(const Section& s) {
  s.only({"mode", "q", "r", "p0", "calibration_samples"});
  pipeline::NoiseSetting n;
  n.automatic = s.one_of("mode", {"fixed", "automatic"}) == "automatic";
  n.fixed.q = s.non_negative("q");
  n.fixed.r = s.positive("r");
  n.fixed.p0 = s.positive("p0");
  n.calibration_samples = static_cast<std::size_t>(s.integer("calibration_samples", 1, 100000000));
  return n;
}

// Keys shared by both time scales.
void load_model(const Section& s, pipeline::FactorStreamParams& p) {
  p.model.lag_order = static_cast<int>(s.integer("lag_order", 1, 64));
  p.model.include_self_lags = s.boolean("include_self_lags");
  p.noise = load_noise(s.child("noise"));
  p.publish_every = static_cast<std::size_t>(s.integer("publish_every", 1, 100000000));
  p.fixed_lag = static_cast<int>(s.integer("fixed_lag", 0, 100000));
}

// Online structure learning on a calibration window (common/pipeline structured_factor_stream.hpp).
pipeline::StructureSetting load_structure(const Section& s) {
  s.only({"calibration_samples", "centre", "causal_order", "prune_threshold"});
  pipeline::StructureSetting st;
  st.calibration_samples = static_cast<std::size_t>(s.integer("calibration_samples", 0, 100000000));
  st.centre = s.boolean("centre");
  st.learn_order = s.one_of("causal_order", {"configured", "lingam"}) == "lingam";
  st.prune_threshold = s.non_negative("prune_threshold");
  if ((st.centre || st.learn_order) && st.calibration_samples == 0) {
    s.fail("calibration_samples", "must be > 0 when centre is true or causal_order is lingam");
  }
  return st;
}

// Required key; "" (or "all") = every instantaneous link. Checked against the channels when data arrives.
std::string graph_text(const Section& s) {
  if (!s.node()["instantaneous_graph"].IsDefined()) s.fail("instantaneous_graph", "missing (required; \"\" = all links)");
  const std::string g = s.node()["instantaneous_graph"].IsNull() ? "" : s.text("instantaneous_graph");
  return g == "all" ? "" : g;
}

}  // namespace

pipeline::AssetPipelineParams load_estimator_params(const std::string& path) {
  const Section root = Section::load_file(path);
  root.only({"sample_level", "condition_level", "health", "output"});
  pipeline::AssetPipelineParams p;

  const Section sample = root.child("sample_level");
  sample.only({"enabled", "lag_order", "include_self_lags", "instantaneous_graph", "noise", "structure",
               "publish_every", "fixed_lag"});
  p.sample_level = sample.boolean("enabled");
  load_model(sample, p.sample);
  p.sample_structure = load_structure(sample.child("structure"));
  p.sample_graph = graph_text(sample);

  const Section cond = root.child("condition_level");
  cond.only({"enabled", "feature", "log_transform", "window_samples", "min_samples", "lag_order",
             "include_self_lags", "instantaneous_graph", "noise", "structure", "publish_every", "fixed_lag"});
  p.condition_graph = graph_text(cond);
  p.condition_level = cond.boolean("enabled");
  const auto feature = io::parse_condition_feature(cond.one_of("feature", {"rms", "meanabs", "kurtosis", "peak"}));
  p.condition.feature = *feature;
  p.condition.log_transform = cond.boolean("log_transform");
  p.condition.window_samples = static_cast<std::size_t>(cond.integer("window_samples", 0, 100000000));
  p.condition.min_samples = static_cast<std::size_t>(cond.integer("min_samples", 1, 100000000));
  load_model(cond, p.condition_model);
  p.condition_structure = load_structure(cond.child("structure"));
  if (!p.sample_level && !p.condition_level) {
    root.fail("sample_level.enabled", "both time scales are disabled: nothing to estimate");
  }
  return p;
}

EstimatorHealthParams load_estimator_health(const std::string& path) {
  const Section root = Section::load_file(path);
  root.only({"sample_level", "condition_level", "health", "output"});
  const Section h = root.child("health");
  h.only({"deadline_s"});
  EstimatorHealthParams p;
  p.deadline_s = h.non_negative("deadline_s");
  // A deadline far beyond any plant cadence is a typo (e.g. milliseconds), not a choice: one day at most.
  if (p.deadline_s > 86400.0) h.fail("deadline_s", "must be <= 86400 s (one day)");
  return p;
}

EstimatorOutputParams load_estimator_output(const std::string& path) {
  const Section root = Section::load_file(path);
  root.only({"sample_level", "condition_level", "health", "output"});
  EstimatorOutputParams p;
  // Optional section: a file written before it existed keeps today's one message per batch.
  if (!root.has("output")) return p;
  const Section o = root.child("output");
  o.only({"factor_messages"});
  p.factor_messages =
      o.one_of("factor_messages", {"batch", "set"}) == "set" ? FactorMessages::Set : FactorMessages::Batch;
  return p;
}

}  // namespace causal::pipeline
