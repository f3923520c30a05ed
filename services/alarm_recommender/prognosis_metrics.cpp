#include "prognosis_metrics.hpp"

#include "causal/metrics/metrics_registry.hpp"

#include <cmath>

namespace causal::recommender {

void PrognosisMetrics::begin(const std::string& asset_group) {
  for (auto it = current_.begin(); it != current_.end();) {
    it = std::get<0>(*it) == asset_group ? current_.erase(it) : std::next(it);
  }
}

void PrognosisMetrics::on_published(const causal_twin::Prognosis& p) {
  const Series s{p.asset_group(), p.channel_name().empty() ? std::to_string(p.channel()) : p.channel_name(), p.level()};
  current_.insert(s);
  shown_.insert(s);
  if (p.reached()) {
    set(s, 0.0, 0.0, 0.0);
  } else if (p.known()) {
    set(s, 3600.0 * p.hours(), 3600.0 * p.hours_low(), 3600.0 * p.hours_high());
  } else {
    set(s, NAN, NAN, NAN);
  }
}

void PrognosisMetrics::end(const std::string& asset_group) {
  for (const auto& s : shown_) {
    if (std::get<0>(s) == asset_group && current_.count(s) == 0) set(s, NAN, NAN, NAN);
  }
}

void PrognosisMetrics::set(const Series& s, double median, double low, double high) {
  const auto& [group, channel, level] = s;
  const char* help = "Time to the next alarm level of an open degradation alarm (Prognosis topic hours x 3600); "
                     "NaN = unknown or no open alarm with that level ahead";
  for (const auto& [bound, value] : {std::pair<const char*, double>{"median", median}, {"low", low}, {"high", high}}) {
    metrics::process_metrics()
        .gauge("prognosis_time_to_level_seconds", help, {{"asset_group", group}, {"channel", channel}, {"level", level}, {"bound", bound}})
        .set(value);
  }
}

}  // namespace causal::recommender
