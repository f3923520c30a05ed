#include "twin_state.hpp"

#include "causal/alarms/factor_names.hpp"
#include "causal/dds/factor_conversions.hpp"

#include <algorithm>
#include <cmath>

namespace causal::web {

// state_json.cpp
std::string state_to_json(const std::map<std::string, GroupState>& groups, const StateCounters& counters,
                          const std::map<std::string, std::string>& info, std::uint64_t version);
std::string overview_to_json(const std::map<std::string, GroupState>& groups,
                             const std::map<std::string, std::string>& info, std::uint64_t version);
std::string group_to_json(const std::string& id, const GroupState& group);

CausalGraph causal_graph(const GroupState& group) {
  CausalGraph graph;
  for (const auto& [outcome, f] : group.factors) {
    graph.index = std::max(graph.index, f.index);
    for (std::size_t i = 0; i < f.names.size(); ++i) {
      const alarms::FactorRef ref = alarms::parse_factor_name(f.names[i], f.channel_count);
      const double value = f.values[i], sd = f.stddev[i];
      if (!ref.valid() || ref.outcome + 1 != outcome || !std::isfinite(value) || !std::isfinite(sd) || sd <= 0.0) {
        ++graph.unusable;
        continue;
      }
      CausalEdge e{ref.regressor + 1, ref.outcome + 1, ref.lag, value, sd, value / sd};
      (e.from == e.to ? graph.self_lags : graph.edges).push_back(e);
    }
  }
  return graph;
}

TwinState::TwinState(StateLimits limits) : limits_(limits) {}

GroupState& TwinState::group_locked(const std::string& asset_group) {
  auto [it, inserted] = groups_.try_emplace(asset_group);
  if (inserted) ++overview_version_;
  return it->second;
}

void TwinState::changed_locked(GroupState* group, bool overview) {
  ++version_;
  if (group) ++group->version;
  if (overview) ++overview_version_;
  changed_.notify_all();
}

void TwinState::on_condition(const causal_twin::ConditionVector& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.condition_vectors;
  const auto& values = in.values();
  const bool finite = std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
  GroupState& g = group_locked(in.asset_group());
  const bool fits = !values.empty() && values.size() == in.channel_names().size() &&
                    (g.channels.empty() || g.channels.size() == values.size());
  if (!finite || !fits) {
    ++counters_.rejected_vectors;
    changed_locked();
    return;
  }
  const bool first = g.channels.empty();
  if (first) g.channels = in.channel_names();
  g.feature = in.feature();
  TrendPoint p{in.snapshot_index(), in.time_ns(), values};
  auto pos = std::lower_bound(g.trend.begin(), g.trend.end(), p.index,
                              [](const TrendPoint& a, std::uint64_t i) { return a.index < i; });
  if (pos != g.trend.end() && pos->index == p.index) {
    ++counters_.duplicates;
    return;
  }
  if (pos == g.trend.end() && !g.trend.empty() && p.index > g.trend.back().index + 1) {
    const std::uint64_t gap = p.index - g.trend.back().index - 1;  // newer than the newest: the indices between
    g.missing += gap;
    counters_.snapshots_missing += gap;
  } else if (pos != g.trend.end() && pos != g.trend.begin() && g.missing > 0) {
    --g.missing;  // a late one between two points fills a hole
    --counters_.snapshots_missing;
  }
  g.trend.insert(pos, std::move(p));
  while (g.trend.size() > limits_.trend_points) {
    g.trend.pop_front();
    ++counters_.trend_points_forgotten;
  }
  changed_locked(&g, first);
}

void TwinState::on_factors(const causal_twin::CausalFactorBatch& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  // The graph shows the real-time model: the condition-level filter. Sample-level factors describe one
  // snapshot's waveform and the smoother lags behind; both are counted, not drawn.
  if (in.time_scale() != causal_twin::CONDITION_LEVEL || in.kind() != causal_twin::FILTER) {
    ++counters_.factor_messages_skipped;
    return;
  }
  if (!dds::validate_causal_factor_batch(in).empty()) {  // outcome range, lengths: the whole batch is refused
    ++counters_.factor_messages_rejected;
    return;
  }
  ++counters_.factor_messages;
  GroupState& g = group_locked(in.asset_group());
  bool changed = false;
  for (const auto& o : in.outcomes()) {
    OutcomeFactors& f = g.factors[o.outcome()];
    if (!f.names.empty() && in.sample_index() < f.index) continue;  // an older estimate re-sent: keep the newest
    f.index = in.sample_index();
    f.time_ns = in.time_ns();
    f.channel_count = in.channel_count();
    f.names = o.factor_names();
    f.values = o.factors();
    f.stddev = o.factor_std();
    changed = true;
  }
  if (changed) changed_locked(&g);
}

std::uint64_t TwinState::index_of_time_locked(const GroupState& g, std::int64_t time_ns, std::uint64_t fallback) const {
  // The snapshot whose time is nearest; the alarm's own evidence index when the trend does not cover it.
  if (g.trend.empty() || time_ns < g.trend.front().time_ns || time_ns > g.trend.back().time_ns) return fallback;
  auto pos = std::lower_bound(g.trend.begin(), g.trend.end(), time_ns,
                              [](const TrendPoint& a, std::int64_t t) { return a.time_ns < t; });
  if (pos == g.trend.end()) return g.trend.back().index;
  if (pos != g.trend.begin() && time_ns - std::prev(pos)->time_ns < pos->time_ns - time_ns) --pos;
  return pos->index;
}

void TwinState::on_alarm(const causal_twin::Alarm& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.alarm_events;
  GroupState& g = group_locked(in.asset_group());
  auto [it, inserted] = g.alarms.try_emplace(in.alarm_id());
  AlarmView& a = it->second;
  if (inserted) {
    // Raised now: the evidence index is the raise. Joined later (a replayed last value): from the raise time.
    a.raised_index = in.state() == causal_twin::RAISED ? in.sample_index()
                                                       : index_of_time_locked(g, in.raised_time_ns(), in.sample_index());
  }
  a.last = in;
  a.arrival = ++arrivals_;
  if (a.acknowledged && !in.acknowledged()) a.acknowledged_by.clear();  // escalated: to be acknowledged anew
  a.acknowledged = in.acknowledged();
  if (!in.shelved()) a.shelved_until_ns = 0;
  a.shelved = in.shelved();
  if (in.state() == causal_twin::CLEARED) {
    a.cleared_index = in.sample_index();
  } else {
    a.cleared_index.reset();
  }
  // Bounded: forget the oldest closed alarms of this group beyond the limit.
  std::size_t closed = 0;
  for (const auto& [id, v] : g.alarms) closed += v.open() ? 0 : 1;
  while (closed > limits_.closed_alarms) {
    auto oldest = g.alarms.end();
    for (auto i = g.alarms.begin(); i != g.alarms.end(); ++i) {
      if (!i->second.open() && (oldest == g.alarms.end() || i->second.arrival < oldest->second.arrival)) oldest = i;
    }
    g.alarms.erase(oldest);
    --closed;
  }
  changed_locked(&g, true);
}

void TwinState::on_recommendation(const causal_twin::Recommendation& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.recommendations;
  GroupState& g = group_locked(in.asset_group());
  RecommendationView& r = g.recommendations[in.recommendation_id()];
  r.last = in;
  r.arrival = ++arrivals_;
  while (g.recommendations.size() > limits_.recommendations) {
    auto oldest = std::min_element(g.recommendations.begin(), g.recommendations.end(),
                                   [](const auto& x, const auto& y) { return x.second.arrival < y.second.arrival; });
    g.recommendations.erase(oldest);
  }
  changed_locked(&g);
}

void TwinState::on_status(const causal_twin::AssetStatus& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.statuses;
  GroupState& g = group_locked(in.asset_group());
  g.status = in;
  changed_locked(&g, true);  // the overview holds every group's status line (sent on change only)
}

void TwinState::on_prognosis(const causal_twin::Prognosis& in) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.prognoses;
  GroupState& g = group_locked(in.asset_group());
  auto [it, inserted] = g.prognoses.try_emplace({static_cast<int>(in.channel()), in.level()}, in);
  if (!inserted) {
    if (in.sample_index() < it->second.sample_index()) {
      ++counters_.prognoses_stale;
      return;
    }
    it->second = in;
  }
  changed_locked(&g);
}

std::string TwinState::default_group() const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, g] : groups_) {
    if (!g.trend.empty()) return id;
  }
  return groups_.empty() ? std::string() : groups_.begin()->first;
}

std::uint64_t TwinState::version() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

bool TwinState::wait_for_change(std::uint64_t seen, std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return version_ != seen; });
}

std::shared_ptr<const std::string> TwinState::json() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!json_ || json_version_ != version_) {
    json_ = std::make_shared<const std::string>(state_to_json(groups_, counters_, info_, version_));
    json_version_ = version_;
  }
  return json_;
}

TwinState::Versions TwinState::versions_locked(const std::string& asset_group) const {
  const auto it = groups_.find(asset_group);
  return {overview_version_, it == groups_.end() ? 0 : it->second.version};
}

TwinState::Versions TwinState::versions(const std::string& asset_group) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return versions_locked(asset_group);
}

bool TwinState::wait_for_change(const std::string& asset_group, Versions seen, std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return versions_locked(asset_group) != seen; });
}

std::string TwinState::page_json(const std::string& asset_group) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const Versions v = versions_locked(asset_group);
  if (overview_json_version_ != v.overview) {
    overview_json_ = overview_to_json(groups_, info_, v.overview);
    overview_json_version_ = v.overview;
  }
  std::string out = "{\"version\":\"" + std::to_string(v.overview) + "." + std::to_string(v.group) +
                    "\",\"overview\":" + overview_json_ + ",\"group\":";
  const auto it = groups_.find(asset_group);
  if (it == groups_.end()) return out + "null}";
  auto& cached = group_json_[asset_group];
  if (cached.second.empty() || cached.first != v.group) cached = {v.group, group_to_json(asset_group, it->second)};
  return out + cached.second + "}";
}

std::vector<std::string> TwinState::channels(const std::string& asset_group) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = groups_.find(asset_group);
  return it == groups_.end() ? std::vector<std::string>{} : it->second.channels;
}

StateCounters TwinState::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

std::optional<GroupState> TwinState::group(const std::string& asset_group) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = groups_.find(asset_group);
  if (it == groups_.end()) return std::nullopt;
  return it->second;
}

void TwinState::set_info(std::string key, std::string value) {
  std::lock_guard<std::mutex> lock(mutex_);
  info_[std::move(key)] = std::move(value);
  changed_locked(nullptr, true);
}

}  // namespace causal::web
