#include "observation_assembler.hpp"

#include <limits>

namespace causal::recommender {

namespace {
constexpr std::size_t kMaxFeatures = 256;  // condition vectors kept per asset group and feature
}  // namespace

void ObservationAssembler::add_factors(const dds::FactorMessage& m, std::vector<AssembledObservation>& out) {
  if (m.kind != causal_twin::FILTER) return;
  sets_ready_.clear();
  sets_.add(m, sets_ready_);
  for (const auto& set : sets_ready_) observe(set, out);
}

void ObservationAssembler::observe(const dds::FactorSet& set, std::vector<AssembledObservation>& out) {
  const int g = set.channel_count;
  AssembledObservation a;
  a.asset_group = set.stream.asset_group;
  a.time_scale = set.stream.time_scale;
  a.lag_order = set.lag_order;
  a.channel_names = set.channel_names;
  a.factor_names = set.factor_names;
  a.covariance_blocks = set.covariance_blocks;
  alarms::Observation& o = a.observation;
  o.index = set.index;
  o.time_ns = set.time_ns;
  o.factors = set.factors;
  o.factor_std = set.factor_std;
  o.innovations.resize(g);
  o.innovation_variances.resize(g);
  if (a.time_scale == causal_twin::SAMPLE_LEVEL) o.mean_nis.resize(g);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < g; ++k) {
    const auto& stats = set.outcomes[static_cast<std::size_t>(k)];
    // No update since the last report: no innovation to judge (NaN = "no value for this channel now").
    const bool fresh = stats.innovation_count > 0;
    o.innovations[k] = fresh ? stats.last_innovation : nan;
    o.innovation_variances[k] = fresh ? stats.last_innovation_variance : nan;
    if (o.mean_nis.size() > 0) o.mean_nis[k] = fresh ? stats.nis_mean : nan;
  }
  if (a.time_scale == causal_twin::SAMPLE_LEVEL) {
    out.push_back(std::move(a));  // sample-level observations carry no condition features
    return;
  }
  const WaitingKey key{set.stream.asset_group, set.stream.feature};
  auto& waiting = waiting_[key];
  waiting.push_back(std::move(a));
  release(key, waiting, out, false);
}

void ObservationAssembler::release(const WaitingKey& key, std::deque<AssembledObservation>& waiting,
                                   std::vector<AssembledObservation>& out, bool all) {
  const auto fit = features_.find(key);
  while (!waiting.empty()) {
    AssembledObservation& a = waiting.front();
    if (fit != features_.end()) {
      const auto vit = fit->second.find(a.observation.time_ns);
      if (vit != fit->second.end()) a.observation.features = vit->second;
    }
    const bool has_features = a.observation.features.size() > 0;
    if (!has_features && !all && waiting.size() <= max_pending_) break;
    out.push_back(std::move(a));
    waiting.pop_front();
  }
}

void ObservationAssembler::add_condition(const std::string& asset_group, const std::string& feature,
                                         std::int64_t time_ns, const Eigen::VectorXd& values,
                                         std::vector<AssembledObservation>& out) {
  const WaitingKey key{asset_group, feature};
  auto& by_time = features_[key];
  by_time[time_ns] = values;
  while (by_time.size() > kMaxFeatures) by_time.erase(by_time.begin());
  if (const auto it = waiting_.find(key); it != waiting_.end()) release(key, it->second, out, false);
}

void ObservationAssembler::flush(std::vector<AssembledObservation>& out) {
  sets_ready_.clear();
  sets_.flush(sets_ready_);
  for (const auto& set : sets_ready_) observe(set, out);
  for (auto& [key, waiting] : waiting_) release(key, waiting, out, true);
}

}  // namespace causal::recommender
