#include "approval_request.hpp"

#include "request_fields.hpp"

#include <cmath>

namespace causal::web {

using nlohmann::json;

namespace {

constexpr double kMaxDuration = 1000000.0;  // snapshots, as causal-approve --duration

}  // namespace

std::string parse_approval(const json& body, const std::string& authenticated_user, ApprovalAsk& out) {
  if (!body.is_object()) return "the body must be a JSON object";
  std::string group, rec, user;
  if (auto why = required_id(body, "asset_group", group); !why.empty()) return why;
  if (auto why = required_id(body, "recommendation_id", rec); !why.empty()) return why;
  if (auto why = acting_user(body, authenticated_user, user); !why.empty()) return why;
  out = ApprovalAsk{};
  if (body.contains("duration_snapshots")) {
    const json& d = body["duration_snapshots"];
    if (!d.is_number_integer() || d.get<double>() < 1.0 || d.get<double>() > kMaxDuration) {
      return "duration_snapshots must be an integer in 1..1000000";
    }
    out.act.duration = d.get<std::uint64_t>();
  }
  out.act.asset_group = group;
  out.act.user = user;
  out.recommendation_id = rec;
  return {};
}

void SourceClock::on_input(const std::string& asset_group, std::uint64_t index, std::int64_t time_ns) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = groups_.find(asset_group);
  if (it == groups_.end()) {
    groups_[asset_group] = Reading{index, time_ns, 0};
    return;
  }
  Reading& r = it->second;
  if (index <= r.index) return;  // a repeat or an older snapshot: the clock only moves forward
  if (index == r.index + 1 && time_ns > r.time_ns) r.cadence_ns = time_ns - r.time_ns;
  r.index = index;
  r.time_ns = time_ns;
}

std::optional<SourceClock::Reading> SourceClock::latest(const std::string& asset_group) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = groups_.find(asset_group);
  if (it == groups_.end()) return std::nullopt;
  return it->second;
}

namespace {

// The plant's latest snapshot as best known (see plan_approval).
SourceClock::Reading latest_snapshot(const GroupState& g, const causal_twin::Recommendation& rec,
                                     const std::optional<SourceClock::Reading>& clock) {
  if (clock) return *clock;
  SourceClock::Reading r;
  r.index = rec.sample_index();
  if (!g.trend.empty()) {
    r.index = g.trend.back().index;
    r.time_ns = g.trend.back().time_ns;
    if (g.trend.size() > 1 && g.trend[g.trend.size() - 2].index + 1 == r.index) {
      r.cadence_ns = r.time_ns - g.trend[g.trend.size() - 2].time_ns;
    }
  }
  return r;
}

}  // namespace

PlannedApproval plan_approval(const ApprovalAsk& ask, const std::optional<GroupState>& group,
                              const std::optional<SourceClock::Reading>& clock, std::uint64_t lead,
                              std::int64_t now_ns) {
  PlannedApproval p;
  const bool known = group && group->recommendations.count(ask.recommendation_id) > 0;
  if (!known) {
    p.status = 404;
    p.why = "recommendation '" + ask.recommendation_id + "' of asset group '" + ask.act.asset_group +
            "' is not known to twin-web (not published, or forgotten)";
    return p;
  }
  for (const auto& [id, view] : group->interventions) {
    if (view.approval && view.approval->recommendation_id() == ask.recommendation_id) {
      p.status = 409;
      p.already = id;
      p.why = "recommendation '" + ask.recommendation_id + "' is already approved (" + id + ")";
      return p;
    }
  }
  const causal_twin::Recommendation& rec = group->recommendations.at(ask.recommendation_id).last;
  const SourceClock::Reading latest = latest_snapshot(*group, rec, clock);
  const std::uint64_t start = latest.index + lead;
  dds::Approval a = dds::make_approval(
      rec, ask.act, start, dds::start_time_of(start, latest.index, latest.time_ns, latest.cadence_ns),
      now_ns);
  if (!a.why.empty()) {
    p.status = 409;
    p.why = a.why;
    return p;
  }
  // The plant refuses a change that overlaps another on the same channel (it would not be the do-operation the twin
  // predicted): refused here first, naming the earlier approval.
  const auto& iv = a.intervention;
  for (const auto& [id, view] : group->interventions) {
    if (!view.approval || view.approval->channel() != iv.channel()) continue;
    const std::uint64_t s0 = view.approval->start_snapshot_index(), n0 = view.approval->duration_snapshots();
    if (iv.start_snapshot_index() < s0 + n0 && s0 < iv.start_snapshot_index() + iv.duration_snapshots()) {
      p.status = 409;
      p.already = id;
      p.why = "the change would overlap approval " + id + " on the same channel (snapshots " + std::to_string(s0) +
              ".." + std::to_string(s0 + n0 - 1) + ")";
      return p;
    }
  }
  p.intervention = iv;
  return p;
}

json approval_json(const causal_twin::Intervention& iv, const ApprovalResult& r) {
  return {{"answered", true},
          {"published", r.published},
          {"error", r.error},
          {"already", r.already},
          {"readers", r.readers},
          {"request_id", iv.request_id()},
          {"asset_group", iv.asset_group()},
          {"recommendation_id", iv.recommendation_id()},
          {"channel", iv.channel()},
          {"change_percent", std::isfinite(iv.change_percent()) ? json(iv.change_percent()) : json(nullptr)},
          {"start_snapshot_index", iv.start_snapshot_index()},
          {"duration_snapshots", iv.duration_snapshots()},
          {"target_channel", iv.target_channel()},
          {"approved_by", iv.approved_by()}};
}

}  // namespace causal::web
