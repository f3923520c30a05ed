// TwinState: the closed prescriptive loop as the live view shows it (read-only): every approved intervention of a
// group (who approved which lever, by how much, over which snapshots) and the twin's check of it after its window
// (predicted interval, observed change, inside, improved, and the lever trust that outcome left). Approval and
// outcome are joined by request id; a re-delivered message replaces the one held (the topics keep the last per id).
#include "intervention_json.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace causal::web {

namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json time_ms(std::int64_t ns) { return ns != 0 ? json(static_cast<double>(ns) / 1e6) : json(nullptr); }

std::string channel_name(const GroupState& g, int channel) {
  return channel >= 1 && static_cast<std::size_t>(channel) <= g.channels.size()
             ? g.channels[static_cast<std::size_t>(channel - 1)]
             : std::string();
}

json outcome_json(const causal_twin::InterventionOutcome& o) {
  return {{"status", o.status()},
          {"start_index", o.start_snapshot_index()},
          {"end_index", o.end_snapshot_index()},
          {"predicted_percent", number(o.predicted_percent())},
          {"predicted_percent_low", number(o.predicted_percent_low())},
          {"predicted_percent_high", number(o.predicted_percent_high())},
          {"confidence", number(o.confidence())},
          {"observed_percent", number(o.observed_percent())},
          {"inside", o.inside()},
          {"improved", o.improved()},
          {"lever_trust", number(o.lever_trust())},
          {"lever_claimed", o.lever_claimed()},
          {"text", o.text()}};
}

json intervention_json(const std::string& id, const InterventionView& v, const GroupState& g) {
  json out = {{"request_id", id}, {"arrival", v.arrival}};
  if (v.approval) {
    const auto& a = *v.approval;
    const std::uint64_t end = a.start_snapshot_index() + a.duration_snapshots() - (a.duration_snapshots() > 0 ? 1 : 0);
    out.update({{"channel", a.channel()},
                {"channel_name", channel_name(g, a.channel())},
                {"change_percent", number(a.change_percent())},
                {"start_index", a.start_snapshot_index()},
                {"end_index", end},
                {"duration", a.duration_snapshots()},
                {"start_time_ms", time_ms(a.start_time_ns())},
                {"recommendation_id", a.recommendation_id()},
                {"target_channel", a.target_channel()},
                {"target_name", channel_name(g, a.target_channel())},
                {"approved_by", a.approved_by()},
                {"approved_time_ms", time_ms(a.approved_time_ns())}});
  } else {
    // Only the outcome is known (the approval was forgotten or not replayed): what the outcome itself says.
    const auto& o = *v.outcome;
    out.update({{"channel", o.channel()},
                {"channel_name", channel_name(g, o.channel())},
                {"change_percent", nullptr},
                {"start_index", nullptr},
                {"end_index", nullptr},
                {"duration", nullptr},
                {"start_time_ms", nullptr},
                {"recommendation_id", o.recommendation_id()},
                {"target_channel", o.target_channel()},
                {"target_name", channel_name(g, o.target_channel())},
                {"approved_by", nullptr},
                {"approved_time_ms", nullptr}});
  }
  out["outcome"] = v.outcome ? outcome_json(*v.outcome) : json(nullptr);
  return out;
}

}  // namespace

json interventions_json(const GroupState& g) {
  std::vector<std::pair<const std::string*, const InterventionView*>> order;
  for (const auto& [id, v] : g.interventions) order.emplace_back(&id, &v);
  std::sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.second->arrival < y.second->arrival; });
  json out = json::array();
  for (const auto& [id, v] : order) out.push_back(intervention_json(*id, *v, g));
  return out;
}

InterventionView& TwinState::intervention_locked(GroupState& g, const std::string& request_id) {
  InterventionView& v = g.interventions[request_id];
  v.arrival = ++arrivals_;
  while (g.interventions.size() > std::max<std::size_t>(1, limits_.interventions)) {  // never the new one
    auto oldest = std::min_element(g.interventions.begin(), g.interventions.end(),
                                   [](const auto& x, const auto& y) { return x.second.arrival < y.second.arrival; });
    g.interventions.erase(oldest);
    ++counters_.interventions_forgotten;
  }
  return v;
}

template <class M>
void TwinState::keep_intervention(const M& in, std::optional<M> InterventionView::*slot, std::uint64_t& received) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++received;
  GroupState& g = group_locked(in.asset_group());
  intervention_locked(g, in.request_id()).*slot = in;
  changed_locked(&g);
}

void TwinState::on_intervention(const causal_twin::Intervention& in) {
  keep_intervention(in, &InterventionView::approval, counters_.interventions);
}

void TwinState::on_intervention_outcome(const causal_twin::InterventionOutcome& in) {
  keep_intervention(in, &InterventionView::outcome, counters_.intervention_outcomes);
}

}  // namespace causal::web
