#include "prognosis_conversions.hpp"

#include "causal/prognosis/prognosis_text.hpp"

namespace causal::recommender {

void to_prognosis(const std::string& asset_group, const advice::PrognosisLine& line, double coverage,
                  causal_twin::Prognosis& out) {
  const prognosis::ChannelPrognosis& p = line.prognosis;
  out.asset_group(asset_group);
  out.channel(static_cast<uint16_t>(p.channel + 1));
  out.level(prognosis::to_string(p.level));
  out.channel_name(line.channel_name);
  out.alarm_id(p.alarm_id);
  out.sample_index(line.index);
  out.time_ns(line.time_ns);
  out.level_ratio(p.ratio);
  out.current_ratio(p.current_ratio);
  out.growth_per_hour(p.growth_per_hour);
  out.known(p.time.known);
  out.reached(p.time.reached);
  out.hours(p.time.hours);
  out.hours_low(p.time.hours_low);
  out.hours_high(p.time.hours_high);
  out.coverage(coverage);
  out.eta_time_ns(p.time.known ? prognosis::eta_ns(line.time_ns, p.time.hours) : 0);
  out.eta_low_time_ns(p.time.known ? prognosis::eta_ns(line.time_ns, p.time.hours_low) : 0);
  out.eta_high_time_ns(p.time.known ? prognosis::eta_ns(line.time_ns, p.time.hours_high) : 0);
  out.text(line.text);
}

void set_next_level(const prognosis::ChannelPrognosis& p, causal_twin::Alarm& out) {
  out.next_level(prognosis::to_string(p.level));
  out.hours_to_next_level(p.time.hours);
  out.hours_to_next_level_low(p.time.hours_low);
  out.hours_to_next_level_high(p.time.hours_high);
}

}  // namespace causal::recommender
