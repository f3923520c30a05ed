#include "open_alarm_metrics.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/metrics/metrics_registry.hpp"

namespace causal::recommender {

void OpenAlarmMetrics::on_published(const causal_twin::Alarm& alarm) {
  if (alarm.state() == causal_twin::CLEARED) {
    const auto it = open_.find(alarm.alarm_id());
    if (it == open_.end()) return;
    const Open was = it->second;
    open_.erase(it);
    refresh(was.group, was.category);
    return;
  }
  Open now{alarm.asset_group(), alarm.category().empty() ? "degradation" : alarm.category(),
           dds::to_string(alarm.severity(), "advisory")};
  const auto it = open_.find(alarm.alarm_id());
  if (it != open_.end() && (it->second.group != now.group || it->second.category != now.category)) {
    const Open was = it->second;
    it->second = now;
    refresh(was.group, was.category);
  }
  open_[alarm.alarm_id()] = now;
  refresh(now.group, now.category);
}

void OpenAlarmMetrics::refresh(const std::string& group, const std::string& category) {
  for (const char* severity : {"advisory", "warning", "critical"}) {
    double n = 0.0;
    for (const auto& [id, o] : open_) {
      if (o.group == group && o.category == category && o.severity == severity) n += 1.0;
    }
    metrics::process_metrics()
        .gauge("alarms_open", "Alarms published and not cleared, by asset group, category and severity",
               {{"asset_group", group}, {"category", category}, {"severity", severity}})
        .set(n);
  }
}

}  // namespace causal::recommender
