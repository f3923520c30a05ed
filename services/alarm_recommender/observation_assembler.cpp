#include "observation_assembler.hpp"

#include <limits>

namespace causal::recommender {

namespace {
constexpr std::size_t kMaxPartial = 64;   // sample indices in assembly at once per stream
constexpr std::size_t kMaxFeatures = 256; // condition vectors kept per asset group and feature
}  // namespace

void ObservationAssembler::add_factors(const dds::FactorMessage& m, std::vector<AssembledObservation>& out) {
  if (m.kind != causal_twin::FILTER) return;
  Stream& s = streams_[{m.asset_group, static_cast<int>(m.time_scale)}];
  s.feature = m.feature;
  Partial& p = s.partial[m.sample_index];
  if (p.outcomes.empty()) p.outcomes.resize(static_cast<std::size_t>(m.channel_count));
  if (m.outcome < 0 || static_cast<std::size_t>(m.outcome) >= p.outcomes.size()) return;
  auto& slot = p.outcomes[static_cast<std::size_t>(m.outcome)];
  if (slot.factor_names.empty()) ++p.received;
  slot = m;
  if (p.received == m.channel_count) {
    complete(s, p, out);
    s.partial.erase(m.sample_index);
  }
  // An index that never completes (a lost message) must not pin memory for ever.
  while (s.partial.size() > kMaxPartial) {
    s.partial.erase(s.partial.begin());
    ++dropped_incomplete_;
  }
}

void ObservationAssembler::complete(Stream& s, Partial& p, std::vector<AssembledObservation>& out) {
  const auto& first = p.outcomes.front();
  const int g = first.channel_count;
  AssembledObservation a;
  a.asset_group = first.asset_group;
  a.time_scale = first.time_scale;
  a.lag_order = first.lag_order;
  alarms::Observation& o = a.observation;
  o.index = first.sample_index;
  o.time_ns = first.time_ns;
  o.innovations.resize(g);
  o.innovation_variances.resize(g);
  if (a.time_scale == causal_twin::SAMPLE_LEVEL) o.mean_nis.resize(g);
  Eigen::Index total = 0;
  for (const auto& m : p.outcomes) total += m.factors.size();
  o.factors.resize(total);
  o.factor_std.resize(total);
  Eigen::Index at = 0;
  bool all_blocks = true;
  for (int k = 0; k < g; ++k) {
    const auto& m = p.outcomes[static_cast<std::size_t>(k)];
    a.channel_names.push_back(m.outcome_name);
    a.factor_names.insert(a.factor_names.end(), m.factor_names.begin(), m.factor_names.end());
    // No update since the last report: no innovation to judge.
    const bool fresh = m.innovation_count > 0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    o.innovations[k] = fresh ? m.last_innovation : nan;
    o.innovation_variances[k] = fresh ? m.last_innovation_variance : nan;
    if (o.mean_nis.size() > 0) o.mean_nis[k] = fresh ? m.nis_mean : nan;
    o.factors.segment(at, m.factors.size()) = m.factors;
    o.factor_std.segment(at, m.factor_std.size()) = m.factor_std;
    at += m.factors.size();
    const auto d = m.factors.size();
    // A 0 x 0 block is valid only for an outcome without factors (then there is nothing to miss).
    all_blocks = all_blocks && m.covariance.rows() == d && m.covariance.cols() == d;
  }
  if (all_blocks) {
    a.covariance_blocks.reserve(static_cast<std::size_t>(g));
    for (const auto& m : p.outcomes) a.covariance_blocks.push_back(m.covariance);
  }
  if (a.time_scale == causal_twin::SAMPLE_LEVEL) {
    out.push_back(std::move(a));  // sample-level observations carry no condition features
    return;
  }
  s.waiting_features.push_back(std::move(a));
  release(s, out, false);
}

void ObservationAssembler::release(Stream& s, std::vector<AssembledObservation>& out, bool all) {
  while (!s.waiting_features.empty()) {
    AssembledObservation& a = s.waiting_features.front();
    const auto fit = features_.find({a.asset_group, s.feature});
    if (fit != features_.end()) {
      const auto vit = fit->second.find(a.observation.time_ns);
      if (vit != fit->second.end()) a.observation.features = vit->second;
    }
    const bool has_features = a.observation.features.size() > 0;
    if (!has_features && !all && s.waiting_features.size() <= max_pending_) break;
    out.push_back(std::move(a));
    s.waiting_features.pop_front();
  }
}

void ObservationAssembler::add_condition(const std::string& asset_group, const std::string& feature,
                                         std::int64_t time_ns, const Eigen::VectorXd& values,
                                         std::vector<AssembledObservation>& out) {
  auto& by_time = features_[{asset_group, feature}];
  by_time[time_ns] = values;
  while (by_time.size() > kMaxFeatures) by_time.erase(by_time.begin());
  const auto it = streams_.find({asset_group, static_cast<int>(causal_twin::CONDITION_LEVEL)});
  if (it != streams_.end() && it->second.feature == feature) release(it->second, out, false);
}

void ObservationAssembler::flush(std::vector<AssembledObservation>& out) {
  for (auto& [key, s] : streams_) release(s, out, true);
}

}  // namespace causal::recommender
