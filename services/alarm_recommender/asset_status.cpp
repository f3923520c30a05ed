#include "asset_status.hpp"

#include "causal/dds/alarm_conversions.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace causal::recommender {

namespace {

// Every field but the index and time.
bool same_status(const causal_twin::AssetStatus& a, const causal_twin::AssetStatus& b) {
  return a.state() == b.state() && a.learning_seen() == b.learning_seen() &&
         a.learning_needed() == b.learning_needed() && a.has_alarm() == b.has_alarm() &&
         a.worst_severity() == b.worst_severity() && a.open_alarms() == b.open_alarms() &&
         a.root_cause_channel() == b.root_cause_channel() && a.root_cause_name() == b.root_cause_name() &&
         a.action() == b.action() && a.prognosis_text() == b.prognosis_text() && a.text() == b.text() &&
         a.unacknowledged_alarms() == b.unacknowledged_alarms() && a.shelved_alarms() == b.shelved_alarms() &&
         a.alarms_per_10_min() == b.alarms_per_10_min() && a.alarm_flood() == b.alarm_flood() &&
         a.standing_alarms() == b.standing_alarms() && a.chattering_alarms() == b.chattering_alarms();
}

std::string upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  return s;
}

}  // namespace

bool AssetStatusBoard::update(const std::string& group, const StatusInput& in, causal_twin::AssetStatus& out) {
  const alarms::AlarmEngine* main = in.condition != nullptr ? in.condition : in.sample;
  if (main == nullptr) return false;
  // The worst open degradation alarm of either time scale (highest severity, then the earliest raised).
  std::vector<alarms::AlarmEvent> open;
  for (const auto* engine : {in.condition, in.sample}) {
    if (engine == nullptr) continue;
    for (auto& e : engine->active_alarms()) {
      if (e.category == alarms::category::kDegradation) open.push_back(std::move(e));
    }
  }
  const alarms::AlarmEvent* worst = nullptr;
  for (const auto& e : open) {
    if (worst == nullptr || e.severity > worst->severity ||
        (e.severity == worst->severity && e.raised_time_ns < worst->raised_time_ns)) {
      worst = &e;
    }
  }
  const auto& p = main->params();
  const auto needed = static_cast<std::uint32_t>(p.warmup_observations + p.baseline_observations);
  const bool learning = !main->baseline_ready();
  causal_twin::AssetStatus s;
  s.asset_group(group);
  s.sample_index(in.index);
  s.time_ns(in.time_ns);
  s.learning_needed(needed);
  s.learning_seen(learning ? static_cast<std::uint32_t>(std::min<std::uint64_t>(main->observations_seen(), needed))
                           : needed);
  s.has_alarm(worst != nullptr);
  s.open_alarms(static_cast<std::uint16_t>(open.size()));
  s.worst_severity(worst != nullptr ? dds::to_idl(worst->severity) : causal_twin::ADVISORY);
  char text[512];
  if (worst != nullptr) {
    const auto& names = main->channel_names();
    const int root = worst->root_cause_channel;
    const bool known = root >= 0 && static_cast<std::size_t>(root) < names.size();
    s.state("alarm");
    s.root_cause_channel(static_cast<std::uint16_t>(known ? root + 1 : 0));
    s.root_cause_name(known ? names[static_cast<std::size_t>(root)] : "");
    const auto action = actions_.find(worst->alarm_id);
    s.action(action != actions_.end() ? action->second : "");
    if (in.prognosis) s.prognosis_text(in.prognosis(*worst));
    const std::string channel =
        worst->channel >= 0 && static_cast<std::size_t>(worst->channel) < names.size()
            ? names[static_cast<std::size_t>(worst->channel)] : "?";
    std::snprintf(text, sizeof text, "%s: %zu open alarm(s), worst %s on %s, root cause %s",
                  upper(alarms::to_string(worst->severity)).c_str(), open.size(), worst->kind.c_str(), channel.c_str(),
                  known ? names[static_cast<std::size_t>(root)].c_str() : "not known yet");
    std::string line = text;
    // A confidence of 0 means "root unknown": never printed as if it were a verdict.
    if (known && worst->root_cause_confidence > 0.0) {
      std::snprintf(text, sizeof text, " (confidence %.2f)", worst->root_cause_confidence);
      line += text;
    }
    if (in.stopped_now) line += "; the machine is not running now";
    s.text(line);
  } else if (in.stopped_now) {
    s.state("stopped");
    std::snprintf(text, sizeof text,
                  "stopped: every channel below %.2f x its baseline level: the machine is not running (an operating "
                  "state, not a fault)%s", p.stopped_ratio, learning ? "; baseline learning paused" : "");
    s.text(text);
  } else if (learning) {
    s.state("learning");
    std::snprintf(text, sizeof text, "learning its baseline: %u of %u observations, no verdict yet",
                  s.learning_seen(), needed);
    s.text(text);
  } else {
    s.state("healthy");
    std::snprintf(text, sizeof text, "healthy: baseline learned from %u observations, no open alarm", needed);
    s.text(text);
  }
  if (in.management) in.management(s);
  const auto it = last_.find(group);
  if (it != last_.end() && same_status(it->second, s)) return false;
  last_[group] = s;
  out = s;
  ++published_;
  return true;
}

bool AssetStatusBoard::refresh(const std::string& group,
                               const std::function<void(causal_twin::AssetStatus&)>& management,
                               causal_twin::AssetStatus& out) {
  const auto it = last_.find(group);
  if (it == last_.end()) return false;
  causal_twin::AssetStatus s = it->second;
  management(s);
  if (same_status(it->second, s)) return false;
  it->second = s;
  out = s;
  ++published_;
  return true;
}

}  // namespace causal::recommender
