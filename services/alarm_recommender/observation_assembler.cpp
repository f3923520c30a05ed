#include "observation_assembler.hpp"

#include <limits>

#include "causal/alarms/observation_builder.hpp"

namespace causal::recommender {

namespace {
// Condition vectors kept per asset group and feature while their factors have not come. The estimator holds
// its structure calibration window (100 snapshots as shipped, configurable) and replays it when the order is
// learned, so the factors of the first vectors arrive a whole window after them: the vectors must outlive
// that window, or the first observations (the alarm engine's baseline) come without features and the level
// alarms lose their baseline. A vector leaves as soon as its observation is released (or one after it: the
// estimator reports in index order), so this bound matters only for an estimator that sends no factors;
// a vector evicted by it is counted (evicted_conditions()).
constexpr std::size_t kMaxFeatures = 8192;
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
  a.time_scale = set.stream.time_scale == causal_twin::SAMPLE_LEVEL ? advice::TimeScale::Sample : advice::TimeScale::Condition;
  a.lag_order = set.lag_order;
  a.channel_names = set.channel_names;
  a.factor_names = set.factor_names;
  a.covariance_blocks = set.covariance_blocks;
  // The shared rule (observation_builder.hpp): the offline chain builds its observations the same way.
  std::vector<alarms::OutcomeReport> outcomes(static_cast<std::size_t>(g));
  for (int k = 0; k < g; ++k) {
    const auto& stats = set.outcomes[static_cast<std::size_t>(k)];
    auto& r = outcomes[static_cast<std::size_t>(k)];
    const Eigen::Index from = set.factor_offset[static_cast<std::size_t>(k)];
    const Eigen::Index n = set.factor_offset[static_cast<std::size_t>(k) + 1] - from;
    r.factors = set.factors.segment(from, n);
    r.factor_std = set.factor_std.segment(from, n);
    r.innovation_count = stats.innovation_count;
    r.nis_mean = stats.nis_mean;
    r.last_innovation = stats.last_innovation;
    r.last_innovation_variance = stats.last_innovation_variance;
  }
  a.observation = alarms::observation_from_outcomes(set.index, set.time_ns, outcomes,
                                                    a.time_scale == advice::TimeScale::Sample);
  if (a.time_scale == advice::TimeScale::Sample) {
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
      if (vit != fit->second.end()) {
        a.observation.features = vit->second.values;
        a.observation.discontinuity = vit->second.discontinuity;
      }
    }
    const bool has_features = a.observation.features.size() > 0;
    if (!has_features && !all && waiting.size() <= max_pending_) break;
    if (fit != features_.end()) {  // vectors up to this time can no longer be joined: observations come in index order
      auto& by_time = fit->second;
      by_time.erase(by_time.begin(), by_time.upper_bound(a.observation.time_ns));
    }
    out.push_back(std::move(a));
    waiting.pop_front();
  }
}

void ObservationAssembler::add_condition(const std::string& asset_group, const std::string& feature,
                                         std::int64_t time_ns, const Eigen::VectorXd& values, bool discontinuity,
                                         std::vector<AssembledObservation>& out) {
  const WaitingKey key{asset_group, feature};
  auto& by_time = features_[key];
  by_time[time_ns] = Condition{values, discontinuity};
  while (by_time.size() > kMaxFeatures) {
    by_time.erase(by_time.begin());
    ++evicted_conditions_;
  }
  if (const auto it = waiting_.find(key); it != waiting_.end()) release(key, it->second, out, false);
}

void ObservationAssembler::flush(std::vector<AssembledObservation>& out) {
  sets_ready_.clear();
  sets_.flush(sets_ready_);
  for (const auto& set : sets_ready_) observe(set, out);
  for (auto& [key, waiting] : waiting_) release(key, waiting, out, true);
}

}  // namespace causal::recommender
