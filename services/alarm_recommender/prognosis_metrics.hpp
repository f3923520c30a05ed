// causal_twin_prognosis_time_to_level_seconds{asset_group, channel, level, bound}: the time to the next alarm level (warning,
// critical, end_of_life) of each open degradation alarm, in seconds from its snapshot (the Prognosis topic
// publishes hours; Prometheus wants base units): bound "median", "low" and "high" (the interval). NaN when the time is unknown (no rising trend,
// too little data, an interval spanning more than a factor of 10) and when the channel no longer has an open
// alarm with that level ahead (a series is never left stale at its last number).
#pragma once

#include "causal_twin.h"

#include <set>
#include <string>
#include <tuple>

namespace causal::recommender {

class PrognosisMetrics {
 public:
  // One round per observation of a group: begin, every published prognosis, end (NaN for the rest).
  void begin(const std::string& asset_group);
  void on_published(const causal_twin::Prognosis& p);
  void end(const std::string& asset_group);

 private:
  using Series = std::tuple<std::string, std::string, std::string>;  // group, channel name, level
  void set(const Series& s, double median, double low, double high);
  std::set<Series> shown_;    // every series exposed so far
  std::set<Series> current_;  // published in this round
};

}  // namespace causal::recommender
