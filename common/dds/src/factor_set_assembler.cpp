#include "causal/dds/factor_set_assembler.hpp"

#include <tuple>

namespace causal::dds {

bool FactorStreamKey::operator<(const FactorStreamKey& o) const {
  return std::tie(asset_group, time_scale, kind, feature) < std::tie(o.asset_group, o.time_scale, o.kind, o.feature);
}

FactorSetCounters& FactorSetCounters::operator+=(const FactorSetCounters& o) {
  accepted += o.accepted;
  duplicates += o.duplicates;
  refused += o.refused;
  complete += o.complete;
  partial += o.partial;
  dropped += o.dropped;
  return *this;
}

FactorSetAssembler::FactorSetAssembler(std::size_t max_pending, IncompletePolicy policy)
    : max_pending_(max_pending < 1 ? 1 : max_pending), policy_(policy) {}

std::string FactorSetAssembler::check(const FactorMessage& m, const Stream& s) const {
  if (m.channel_count < 1) return "channel count " + std::to_string(m.channel_count) + " < 1";
  if (s.channel_count != 0 && m.channel_count != s.channel_count) {
    return "channel count " + std::to_string(m.channel_count) + " differs from the stream's " +
           std::to_string(s.channel_count);
  }
  if (m.outcome < 0 || m.outcome >= m.channel_count) {
    return "outcome " + std::to_string(m.outcome + 1) + " is outside 1.." + std::to_string(m.channel_count);
  }
  const auto d = m.factors.size();
  if (static_cast<Eigen::Index>(m.factor_names.size()) != d || m.factor_std.size() != d) {
    return "factor names, factors and std devs differ in length";
  }
  // A non-finite estimate would reach the alarm engine or the CSV silently: refuse it (the filter itself
  // never publishes one; this guards against a corrupt or foreign writer).
  if (!m.factors.allFinite() || !m.factor_std.allFinite() || !m.covariance.allFinite()) {
    return "non-finite factor, std dev or covariance";
  }
  return {};
}

FactorSetAssembler::AddStatus FactorSetAssembler::add(const FactorMessage& m, std::vector<FactorSet>& out) {
  const auto stream_it = streams_.try_emplace(FactorStreamKey{m.asset_group, m.time_scale, m.kind, m.feature}).first;
  const FactorStreamKey& key = stream_it->first;
  Stream& s = stream_it->second;
  if (std::string problem = check(m, s); !problem.empty()) {
    last_problem_ = std::move(problem);
    ++s.counters.refused;
    return AddStatus::Refused;
  }
  if (s.released && m.sample_index <= *s.released) {
    ++s.counters.duplicates;  // re-sent after a restart, or replayed history
    return AddStatus::Duplicate;
  }
  s.channel_count = m.channel_count;
  auto [it, created] = s.pending.try_emplace(m.sample_index);
  Pending& p = it->second;
  if (created) {
    p.outcomes.resize(static_cast<std::size_t>(m.channel_count));
    p.time_ns = m.time_ns;
    p.lag_order = m.lag_order;
  }
  auto& slot = p.outcomes[static_cast<std::size_t>(m.outcome)];
  if (slot) {
    ++s.counters.duplicates;  // first copy kept: a set never mixes two sends of one outcome
    return AddStatus::Duplicate;
  }
  slot = m;
  ++p.present;
  ++s.counters.accepted;
  if (p.present == s.channel_count) {
    // Every outcome has delivered this index, and each outcome delivers in index order: an older set
    // still missing an outcome will never get it. Release it now rather than holding this one back.
    while (s.pending.begin()->first < m.sample_index) release(key, s, s.pending.begin(), out);
  }
  drain(key, s, out);
  return AddStatus::Accepted;
}

void FactorSetAssembler::drain(const FactorStreamKey& key, Stream& s, std::vector<FactorSet>& out) {
  for (;;) {
    while (!s.pending.empty() && s.pending.begin()->second.present == s.channel_count) {
      release(key, s, s.pending.begin(), out);
    }
    // The front is incomplete here, and nothing behind it is complete: an outcome has stopped arriving.
    // Bound the wait.
    if (s.pending.size() <= max_pending_) return;
    release(key, s, s.pending.begin(), out);
  }
}

void FactorSetAssembler::release(const FactorStreamKey& key, Stream& s,
                                 std::map<std::uint64_t, Pending>::iterator it, std::vector<FactorSet>& out) {
  const std::uint64_t index = it->first;
  const bool complete = it->second.present == s.channel_count;
  if (complete || policy_ == IncompletePolicy::ReleasePartial) {
    ++(complete ? s.counters.complete : s.counters.partial);
    out.push_back(make_set(key, index, it->second));
    if (key.time_scale == causal_twin::CONDITION_LEVEL) s.emitted.record(index);
  } else {
    ++s.counters.dropped;
  }
  s.released = index;  // pending indices are above the frontier, and the front is the lowest
  s.pending.erase(it);
}

FactorSet FactorSetAssembler::make_set(const FactorStreamKey& key, std::uint64_t index, const Pending& p) {
  const int g = static_cast<int>(p.outcomes.size());
  FactorSet set;
  set.stream = key;
  set.channel_count = g;
  set.lag_order = p.lag_order;
  set.index = index;
  set.time_ns = p.time_ns;
  set.complete = p.present == g;
  set.present.assign(static_cast<std::size_t>(g), false);
  set.channel_names.assign(static_cast<std::size_t>(g), std::string());
  set.outcomes.assign(static_cast<std::size_t>(g), OutcomeStats{});
  set.factor_offset.assign(static_cast<std::size_t>(g) + 1, 0);
  Eigen::Index total = 0;
  for (int k = 0; k < g; ++k) {
    const auto& m = p.outcomes[static_cast<std::size_t>(k)];
    set.factor_offset[static_cast<std::size_t>(k)] = total;
    if (m) total += m->factors.size();
  }
  set.factor_offset[static_cast<std::size_t>(g)] = total;
  set.factors.resize(total);
  set.factor_std.resize(total);
  bool all_blocks = set.complete;
  for (int k = 0; k < g; ++k) {
    const auto& m = p.outcomes[static_cast<std::size_t>(k)];
    if (!m) continue;
    const auto ku = static_cast<std::size_t>(k);
    set.present[ku] = true;
    set.channel_names[ku] = m->outcome_name;
    set.factor_names.insert(set.factor_names.end(), m->factor_names.begin(), m->factor_names.end());
    const Eigen::Index at = set.factor_offset[ku], d = m->factors.size();
    set.factors.segment(at, d) = m->factors;
    set.factor_std.segment(at, d) = m->factor_std;
    set.outcomes[ku] = OutcomeStats{m->innovation_count, m->innovation_mean,        m->nis_mean,
                                    m->last_innovation,  m->last_innovation_variance, m->rejected_samples};
    // A 0 x 0 block is valid only for an outcome without factors (then there is nothing to miss).
    all_blocks = all_blocks && m->covariance.rows() == d && m->covariance.cols() == d;
  }
  if (all_blocks) {
    set.covariance_blocks.reserve(static_cast<std::size_t>(g));
    for (const auto& m : p.outcomes) set.covariance_blocks.push_back(m->covariance);
  }
  return set;
}

void FactorSetAssembler::flush(std::vector<FactorSet>& out) {
  for (auto& [key, s] : streams_) {
    while (!s.pending.empty()) release(key, s, s.pending.begin(), out);
  }
}

FactorSetCounters FactorSetAssembler::counters() const {
  FactorSetCounters total;
  for (const auto& [key, s] : streams_) total += s.counters;
  return total;
}

std::vector<FactorStreamReport> FactorSetAssembler::streams() const {
  std::vector<FactorStreamReport> reports;
  for (const auto& [key, s] : streams_) {
    FactorStreamReport r;
    r.stream = key;
    r.counters = s.counters;
    r.gaps_tracked = key.time_scale == causal_twin::CONDITION_LEVEL;
    if (r.gaps_tracked) r.missing = s.emitted.missing();
    reports.push_back(std::move(r));
  }
  return reports;
}

std::size_t FactorSetAssembler::pending() const {
  std::size_t n = 0;
  for (const auto& [key, s] : streams_) n += s.pending.size();
  return n;
}

}  // namespace causal::dds
