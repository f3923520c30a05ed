// causal_twin_alarms_open{asset_group, category, severity}: the alarms this recommender has published and not
// yet cleared, by asset group, category (degradation, data_quality, health, operating_change) and severity
// (advisory, warning, critical). Fed with every alarm message the recommender writes; a group's three
// severities are always exposed, so a cleared alarm brings its series back to 0 instead of leaving it stale.
#pragma once

#include "causal_twin.h"

#include <map>
#include <string>

namespace causal::recommender {

class OpenAlarmMetrics {
 public:
  void on_published(const causal_twin::Alarm& alarm);
  std::size_t open() const { return open_.size(); }

 private:
  struct Open {
    std::string group, category, severity;
  };
  void refresh(const std::string& group, const std::string& category);
  std::map<std::string, Open> open_;  // by alarm id
};

}  // namespace causal::recommender
