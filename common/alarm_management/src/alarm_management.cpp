#include "causal/alarm_management/alarm_management.hpp"

#include <algorithm>
#include <tuple>
#include <utility>

#include "causal/io/enum_names.hpp"

namespace causal::alarm_management {

namespace {

constexpr auto kActionNames = io::enum_names<ActionKind>(
    {{ActionKind::Acknowledge, "acknowledge"}, {ActionKind::Shelve, "shelve"}, {ActionKind::Unshelve, "unshelve"}});

constexpr auto kRefusalNames = io::enum_names<Refusal>({{Refusal::None, "none"},
                                                        {Refusal::BadRequest, "bad_request"},
                                                        {Refusal::UnknownAlarm, "unknown_alarm"},
                                                        {Refusal::NotApplicable, "not_applicable"}});

}  // namespace

const char* to_string(ActionKind kind) { return kActionNames.name(kind, "unknown"); }

std::optional<ActionKind> parse_action(std::string_view text) { return kActionNames.parse(text); }

const char* to_string(Refusal refusal) { return kRefusalNames.name(refusal, "unknown"); }

std::string source_of(const std::string& alarm_id) {
  const auto slash = alarm_id.rfind('/');
  if (slash == std::string::npos) return alarm_id;
  return alarm_id.substr(0, slash);
}

namespace {

// Printable text only (no control characters): the strings reach logs, CSV files and the page.
bool printable(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f; });
}

// Drops the times at or before `latest - window` (data time only moves forward per stream; a late event is kept).
void prune(std::vector<std::int64_t>& times, std::int64_t latest, std::int64_t window) {
  times.erase(std::remove_if(times.begin(), times.end(), [&](std::int64_t t) { return t <= latest - window; }),
              times.end());
}

unsigned count_in(const std::vector<std::int64_t>& times, std::int64_t t, std::int64_t window) {
  return static_cast<unsigned>(
      std::count_if(times.begin(), times.end(), [&](std::int64_t x) { return x > t - window && x <= t; }));
}

// The first problem of a request's own fields ("" none).
std::string request_problem(const ActionRequest& r, const ManagementLimits& limits) {
  for (const auto* s : {&r.request_id, &r.asset_group, &r.alarm_id, &r.user}) {
    if (s->empty()) return "request id, asset group, alarm id and user must not be empty";
  }
  for (const auto* s : {&r.request_id, &r.asset_group, &r.alarm_id, &r.user, &r.reason}) {
    if (s->size() > limits.max_text) return "a text field is longer than " + std::to_string(limits.max_text);
    if (!printable(*s)) return "a text field holds control characters";
  }
  if (r.time_ns <= 0) return "the action's time must be set (UTC ns)";
  if (r.action == ActionKind::Shelve && r.reason.empty()) return "shelving needs a reason";
  if (r.action != ActionKind::Shelve && r.until_ns != 0) return "'until' is for shelving only";
  return {};
}

}  // namespace

AlarmManager::AlarmManager(ManagementLimits limits) : limits_(limits) {}

EventFlags AlarmManager::on_event(const AlarmEventView& e) {
  auto& a = alarms_[e.alarm_id];
  a.asset_group = e.asset_group;
  const std::string source = source_of(e.alarm_id);
  if (e.state == EventState::Raised) {
    const bool first = a.raised_time_ns == 0 || !a.open;
    a.open = true;
    a.acknowledged = false;
    a.raised_time_ns = e.raised_time_ns;
    if (first) {
      auto& by_source = raises_by_source_[{e.asset_group, source}];
      by_source.push_back(e.raised_time_ns);
      prune(by_source, e.raised_time_ns, limits_.chatter_window_ns);
      auto& by_group = raises_by_group_[e.asset_group];
      by_group.push_back(e.raised_time_ns);
      prune(by_group, e.raised_time_ns, limits_.flood_window_ns);
    }
  } else if (e.state == EventState::Escalated) {
    a.open = true;
    a.acknowledged = false;  // a worse severity is annunciated again
    if (a.raised_time_ns == 0) a.raised_time_ns = e.raised_time_ns;
  } else if (a.open) {
    a.open = false;
    cleared_order_.push_back(e.alarm_id);
    forget_old_cleared();
  }
  return flags(e.alarm_id);
}

EventFlags AlarmManager::on_republished(const AlarmEventView& e) {
  const auto it = alarms_.find(e.alarm_id);
  if (it != alarms_.end() && it->second.open == (e.state != EventState::Cleared)) return flags(e.alarm_id);
  return on_event(e);
}

EventFlags AlarmManager::flags(const std::string& alarm_id) const {
  EventFlags f;
  if (const auto it = alarms_.find(alarm_id); it != alarms_.end()) f.acknowledged = it->second.acknowledged;
  f.shelved = shelved_.count(source_of(alarm_id)) > 0;
  return f;
}

ActionOutcome AlarmManager::refuse(Refusal why, std::string error) {
  ++counters_.refused[why];
  ActionOutcome o;
  o.refusal = why;
  o.error = std::move(error);
  return o;
}

ActionOutcome AlarmManager::apply(const ActionRequest& r, std::int64_t now_ns) {
  if (const auto it = outcomes_.find(r.request_id); it != outcomes_.end() && !r.request_id.empty()) {
    ++counters_.repeated;
    ActionOutcome o = it->second;
    o.repeated = true;
    return o;
  }
  ActionOutcome o;
  if (const auto problem = request_problem(r, limits_); !problem.empty()) {
    o = refuse(Refusal::BadRequest, problem);
  } else if (auto it = alarms_.find(r.alarm_id); it == alarms_.end()) {
    o = refuse(Refusal::UnknownAlarm, "unknown alarm id '" + r.alarm_id + "'");
  } else if (it->second.asset_group != r.asset_group) {
    o = refuse(Refusal::UnknownAlarm,
               "alarm '" + r.alarm_id + "' belongs to asset group '" + it->second.asset_group + "'");
  } else {
    o = act(r, it->second, now_ns);
  }
  if (!o.applied) {
    const auto f = flags(r.alarm_id);
    o.acknowledged = f.acknowledged;
    o.shelved = f.shelved;
  }
  remember(r.request_id, o);
  return o;
}

ActionOutcome AlarmManager::act(const ActionRequest& r, AlarmRecord& alarm, std::int64_t now_ns) {
  const std::string source = source_of(r.alarm_id);
  switch (r.action) {
    case ActionKind::Acknowledge:
      if (alarm.acknowledged) return refuse(Refusal::NotApplicable, "alarm '" + r.alarm_id + "' is acknowledged");
      alarm.acknowledged = true;
      break;
    case ActionKind::Shelve:
      if (r.until_ns <= now_ns) return refuse(Refusal::BadRequest, "the shelving ends before now");
      if (r.until_ns - now_ns > limits_.max_shelve_ns) {
        return refuse(Refusal::BadRequest, "shelving is limited to " +
                                               std::to_string(limits_.max_shelve_ns / 3'600'000'000'000LL) + " h");
      }
      shelved_[source] = Shelving{alarm.asset_group, r.alarm_id, r.until_ns};  // a new end replaces the old one
      break;
    case ActionKind::Unshelve:
      if (shelved_.erase(source) == 0) return refuse(Refusal::NotApplicable, "'" + source + "' is not shelved");
      break;
  }
  ++counters_.applied;
  ActionOutcome o;
  o.applied = true;
  const auto f = flags(r.alarm_id);
  o.acknowledged = f.acknowledged;
  o.shelved = f.shelved;
  return o;
}

void AlarmManager::remember(const std::string& request_id, const ActionOutcome& outcome) {
  if (request_id.empty()) return;
  outcomes_[request_id] = outcome;
  outcome_order_.push_back(request_id);
  while (outcome_order_.size() > limits_.remembered_requests) {
    outcomes_.erase(outcome_order_.front());
    outcome_order_.pop_front();
  }
}

void AlarmManager::forget_old_cleared() {
  while (cleared_order_.size() > limits_.remembered_cleared) {
    const auto it = alarms_.find(cleared_order_.front());
    if (it != alarms_.end() && !it->second.open) alarms_.erase(it);  // re-raised ones stay
    cleared_order_.pop_front();
  }
}

std::vector<ExpiredShelve> AlarmManager::expire(std::int64_t now_ns) {
  std::vector<ExpiredShelve> out;
  for (auto it = shelved_.begin(); it != shelved_.end();) {
    if (it->second.until_ns <= now_ns) {
      out.push_back({it->second.asset_group, it->first, it->second.alarm_id, it->second.until_ns});
      it = shelved_.erase(it);
    } else {
      ++it;
    }
  }
  std::sort(out.begin(), out.end(), [](const ExpiredShelve& a, const ExpiredShelve& b) {
    return std::tie(a.until_ns, a.source) < std::tie(b.until_ns, b.source);
  });
  counters_.expired += out.size();
  return out;
}

GroupHealth AlarmManager::health(const std::string& group, std::int64_t t_ns) const {
  GroupHealth h;
  for (const auto& [id, a] : alarms_) {
    if (a.asset_group != group || !a.open) continue;
    ++h.open;
    if (!a.acknowledged) ++h.unacknowledged;
    if (t_ns - a.raised_time_ns > limits_.standing_after_ns) ++h.standing;
  }
  for (const auto& [source, s] : shelved_) {
    if (s.asset_group == group) ++h.shelved;
  }
  if (const auto it = raises_by_group_.find(group); it != raises_by_group_.end()) {
    h.alarms_per_10_min = count_in(it->second, t_ns, limits_.flood_window_ns);
  }
  h.flood = h.alarms_per_10_min > limits_.flood_above;
  for (auto it = raises_by_source_.lower_bound({group, std::string()}); it != raises_by_source_.end(); ++it) {
    if (it->first.first != group) break;
    if (count_in(it->second, t_ns, limits_.chatter_window_ns) >= limits_.chatter_raises) ++h.chattering;
  }
  return h;
}

}  // namespace causal::alarm_management
