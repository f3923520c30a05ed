#include "causal/prognosis/alarm_prognosis.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace causal::prognosis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One event for the alarm and the forecast: a level is "reached" exactly when the alarm engine's level event
// reached it (the median of the last level_window snapshots at ratio x the reference), which is also when the
// alarm escalates to it. A filtered trend already at the level while that median is not is "unknown" (the
// crossing is being confirmed), never "reached" and never a time in the past.
void one_event(bool engine_reached, int level_window, TimeToLevel& time) {
  if (engine_reached) {
    time.known = time.reached = true;
    time.hours = time.hours_low = time.hours_high = 0.0;
    time.why.clear();
  } else if (time.reached) {
    time.known = time.reached = false;
    time.hours = time.hours_low = time.hours_high = kNaN;
    time.why = "at the level by the trend, not yet by the median of the last " + std::to_string(level_window) +
               " snapshots (the alarm's level): crossing being confirmed";
  }
}

ChannelPrognosis prognosis_for(const ChannelTrends& trends, const alarms::AlarmEngine& engine,
                               const EngineBaselines& b, const alarms::AlarmEvent& alarm, Level level,
                               std::uint64_t index) {
  ChannelPrognosis p;
  p.channel = alarm.channel;
  p.alarm_id = alarm.alarm_id;
  p.onset_index = alarm.onset_index;
  p.level = level;
  p.ratio = trends.ratio(level, engine.params().warning_ratio, engine.params().critical_ratio);
  const DegradationTrend& t = trends.trend(alarm.channel);
  // The levels are multiples of the reference the alarm's severities are judged against (AlarmEngine::level_event).
  const alarms::LevelEvent event = engine.level_event(alarm.channel);
  const double base = event.ratio_scale ? event.reference_log : b.log_location[alarm.channel];
  p.current_ratio = t.started() && std::isfinite(base) ? std::exp(t.state().x[0] - base) : kNaN;
  p.growth_per_hour = t.started() ? t.state().x[1] : kNaN;
  const std::uint64_t points = index >= alarm.onset_index ? index - alarm.onset_index + 1 : 0;
  if (std::isfinite(base)) {
    p.time = trends.time_to(alarm.channel, base, p.ratio, points, alarm.onset_time_ns, b.log_scale[alarm.channel]);
    if (event.ratio_scale) one_event(engine.level_reached(alarm.channel, p.ratio), engine.params().level_window, p.time);
  } else {
    p.time.hours = p.time.hours_low = p.time.hours_high = kNaN;
    p.time.why = "no baseline for this channel";
  }
  return p;
}

}  // namespace

EngineBaselines baselines_of(const alarms::AlarmEngine& engine) {
  const int g = engine.channel_count();
  EngineBaselines b{Eigen::VectorXd::Constant(g, kNaN), Eigen::VectorXd::Constant(g, kNaN)};
  const bool logged = engine.params().feature_log_transform;
  for (int k = 0; k < g; ++k) {
    const auto d = engine.channel_diagnostics(k).feature;
    if (!d.monitored) continue;
    if (logged) {
      b.log_location[k] = d.baseline_location;
      b.log_scale[k] = d.baseline_scale;
    } else if (d.baseline_location > 0) {  // raw units: relative spread is the log spread to first order
      b.log_location[k] = std::log(d.baseline_location);
      b.log_scale[k] = d.baseline_scale / d.baseline_location;
    }
  }
  return b;
}

int observe_for_prognosis(ChannelTrends& trends, const alarms::AlarmEngine& engine, const alarms::Observation& obs,
                          bool discontinuity) {
  const int g = trends.channels();
  if (obs.features.size() != g) return 0;  // no features: nothing to trend (counted by the engine as it sees fit)
  const EngineBaselines b = baselines_of(engine);
  Eigen::VectorXd y(g);
  for (int k = 0; k < g; ++k) y[k] = obs.features[k] > 0 ? std::log(obs.features[k]) : kNaN;
  // A non-positive or non-finite feature of a channel with a baseline is refused by the trend (counted).
  for (int k = 0; k < g; ++k)
    if (!std::isfinite(y[k]) && std::isfinite(obs.features[k])) y[k] = std::numeric_limits<double>::infinity();
  return trends.observe(obs.time_ns, y, b.log_scale, discontinuity);
}

std::vector<ChannelPrognosis> open_alarm_prognoses(const ChannelTrends& trends, const alarms::AlarmEngine& engine,
                                                   std::uint64_t index) {
  // The open degradation alarm with the earliest onset of each channel: the trend's story starts there.
  std::map<int, alarms::AlarmEvent> first;
  for (const auto& e : engine.active_alarms()) {
    if (e.category != alarms::category::kDegradation || e.channel < 0 || e.channel >= trends.channels()) continue;
    auto it = first.find(e.channel);
    if (it == first.end() || e.onset_index < it->second.onset_index) first[e.channel] = e;
  }
  std::vector<ChannelPrognosis> out;
  if (first.empty()) return out;
  const EngineBaselines b = baselines_of(engine);
  for (const auto& [channel, alarm] : first)
    for (Level level : {Level::warning, Level::critical, Level::end_of_life})
      out.push_back(prognosis_for(trends, engine, b, alarm, level, index));
  return out;
}

bool next_level_of(const ChannelTrends& trends, const alarms::AlarmEngine& engine, const alarms::AlarmEvent& event,
                   ChannelPrognosis& out) {
  if (event.category != alarms::category::kDegradation || event.state == alarms::AlarmState::Cleared) return false;
  if (event.channel < 0 || event.channel >= trends.channels()) return false;
  const Level next = event.severity == alarms::Severity::Advisory  ? Level::warning
                     : event.severity == alarms::Severity::Warning ? Level::critical
                                                                   : Level::end_of_life;
  out = prognosis_for(trends, engine, baselines_of(engine), event, next, event.index);
  return true;
}

}  // namespace causal::prognosis
