#include "causal/alarms/condition_alarm_chain.hpp"

#include <optional>
#include <stdexcept>
#include <utility>

#include "causal/alarms/observation_builder.hpp"

namespace causal::alarms {

struct ConditionAlarmChain::Impl {
  std::string group;
  std::vector<std::string> names;
  AlarmParams alarm_params;
  pipeline::AssetPipeline estimator;
  pipeline::PipelineOutput scratch;
  std::unique_ptr<AlarmEngine> engine;
  std::vector<std::string> factor_names;
  // Accepted condition vectors by time (what the estimator publishes on condition_vector); the recommender
  // joins each observation with the vector of the same time.
  struct Condition {
    Eigen::VectorXd values;
    bool discontinuity = false;
  };
  std::map<std::int64_t, Condition> conditions;
  // Filter reports of one index being collected (every outcome reports the same index at once).
  std::map<std::uint64_t, std::vector<std::optional<pipeline::FactorReport>>> pending;

  Impl(std::string g, std::vector<std::string> n, pipeline::AssetPipelineParams e, AlarmParams a)
      : group(std::move(g)), names(std::move(n)), alarm_params(a), estimator(std::move(e)) {}

  void take_reports(ChainOutput& out, const std::function<void(const Observation&)>& hook) {
    const int g = static_cast<int>(names.size());
    for (auto& r : scratch.condition_reports) {
      if (r.kind != pipeline::EstimateKind::Filter) continue;  // the recommender judges filter estimates
      auto& slot = pending[r.sample_index];
      slot.resize(static_cast<std::size_t>(g));
      slot[static_cast<std::size_t>(r.outcome)] = std::move(r);
    }
    scratch.condition_reports.clear();
    while (!pending.empty()) {
      auto it = pending.begin();
      for (const auto& o : it->second)
        if (!o) return;  // in index order: wait for the rest of the oldest index
      observe(it->first, it->second, out, hook);
      pending.erase(it);
    }
  }

  void observe(std::uint64_t index, const std::vector<std::optional<pipeline::FactorReport>>& reports, ChainOutput& out,
               const std::function<void(const Observation&)>& hook) {
    std::vector<OutcomeReport> outcomes;
    for (const auto& r : reports) {
      OutcomeReport o;
      o.factors = r->factors;
      o.factor_std = r->std_devs;
      o.innovation_count = r->innovation_count;
      o.nis_mean = r->nis_mean;
      o.last_innovation = r->last_innovation;
      o.last_innovation_variance = r->last_innovation_variance;
      outcomes.push_back(std::move(o));
    }
    Observation obs = observation_from_outcomes(index, reports.front()->time_ns, outcomes, false);
    if (const auto c = conditions.find(obs.time_ns); c != conditions.end()) {
      obs.features = c->second.values;
      obs.discontinuity = c->second.discontinuity;
    }
    if (!engine) {
      const auto* stream = estimator.condition_stream();
      factor_names = stream ? stream->layout().factor_names() : std::vector<std::string>{};
      engine = std::make_unique<AlarmEngine>(group, names, factor_names, alarm_params);
    }
    if (hook) hook(obs);
    for (auto& e : engine->observe(obs)) out.events.push_back(std::move(e));
    ++out.observations;
  }
};

ConditionAlarmChain::ConditionAlarmChain(std::string asset_group, std::vector<std::string> channel_names,
                                         pipeline::AssetPipelineParams estimator, AlarmParams alarms) {
  if (channel_names.empty()) throw std::invalid_argument("ConditionAlarmChain: channel_names must not be empty");
  alarms.validate();
  estimator.sample_level = false;  // condition vectors only
  estimator.condition_level = true;
  impl_ = std::make_unique<Impl>(std::move(asset_group), std::move(channel_names), std::move(estimator), alarms);
  impl_->estimator.set_channel_names(impl_->names);
}

ConditionAlarmChain::~ConditionAlarmChain() = default;
ConditionAlarmChain::ConditionAlarmChain(ConditionAlarmChain&&) noexcept = default;
ConditionAlarmChain& ConditionAlarmChain::operator=(ConditionAlarmChain&&) noexcept = default;

bool ConditionAlarmChain::feed(const Eigen::VectorXd& values, std::uint64_t snapshot_index, bool discontinuity,
                               std::int64_t time_ns, ChainOutput& out, std::string* problem) {
  Impl& m = *impl_;
  if (values.size() != static_cast<Eigen::Index>(m.names.size())) {
    if (problem) *problem = "condition vector has " + std::to_string(values.size()) + " values for " +
                            std::to_string(m.names.size()) + " channels";
    return false;
  }
  m.scratch.clear();
  const auto check = m.estimator.feed_condition(values, snapshot_index, discontinuity, time_ns, m.scratch);
  if (!check.ok) {
    if (problem) *problem = check.problem;
    return false;
  }
  m.conditions[time_ns] = Impl::Condition{values, discontinuity};
  m.take_reports(out, on_observation);
  return true;
}

void ConditionAlarmChain::finish(ChainOutput& out) {
  Impl& m = *impl_;
  m.scratch.clear();
  m.estimator.finish(m.scratch);
  m.take_reports(out, on_observation);
}

const pipeline::AssetPipeline& ConditionAlarmChain::estimator() const { return impl_->estimator; }
const AlarmEngine* ConditionAlarmChain::engine() const { return impl_->engine.get(); }
const std::vector<std::string>& ConditionAlarmChain::factor_names() const { return impl_->factor_names; }

}  // namespace causal::alarms
