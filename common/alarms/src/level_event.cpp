// The level event of a channel (AlarmEngine::level_event): warning, critical and end of life as multiples of
// the channel's reference, judged by the median of the last level_window values; the severities of the
// channel's alarms and the forecast's "reached" both read it.
#include <cmath>
#include <stdexcept>

#include "engine_internal.hpp"

namespace causal::alarms {

using detail::kNaN;

bool AlarmEngine::Impl::ratio_scale(int c) const {
  const auto& f = ch[static_cast<std::size_t>(c)].feature;
  return p.feature_log_transform && f.monitored && std::isfinite(f.reference_location);
}

bool AlarmEngine::Impl::level_reached(int c, double ratio) const {
  const auto& cs = ch[static_cast<std::size_t>(c)];
  return ratio_scale(c) && cs.any_active() && std::isfinite(cs.level_peak) && cs.level_peak >= std::log(ratio);
}

bool AlarmEngine::Impl::escalate(int c, int k) {
  auto& slot = ch[static_cast<std::size_t>(c)].slots[static_cast<std::size_t>(k)];
  Severity earned = Severity::Advisory;
  if (ratio_scale(c)) {
    // One event for every alarm of the channel and for its forecast: the level ladder of the channel's level
    // event (AlarmEngine::level_event), whatever kind of evidence raised the alarm.
    earned = level_reached(c, p.critical_ratio)  ? Severity::Critical
             : level_reached(c, p.warning_ratio) ? Severity::Warning
                                                 : Severity::Advisory;
  } else {  // no ratio scale: the kind's own level in sigmas, held for escalation_persistence observations
    const Severity level = severity_for(c, k);
    slot.warning_run = static_cast<int>(level) >= static_cast<int>(Severity::Warning) ? slot.warning_run + 1 : 0;
    slot.critical_run = level == Severity::Critical ? slot.critical_run + 1 : 0;
    earned = slot.critical_run >= p.escalation_persistence  ? Severity::Critical
             : slot.warning_run >= p.escalation_persistence ? Severity::Warning
                                                            : Severity::Advisory;
  }
  if (static_cast<int>(earned) <= static_cast<int>(slot.severity)) return false;  // severities only escalate
  slot.severity = earned;
  return true;
}

LevelEvent AlarmEngine::level_event(int channel) const {
  const Impl& m = *impl_;
  if (channel < 0 || channel >= m.channels()) throw std::invalid_argument("level_event: channel out of range");
  const auto& cs = m.ch[static_cast<std::size_t>(channel)];
  LevelEvent e;
  e.ratio_scale = m.ratio_scale(channel);
  e.reference_log = e.ratio_scale ? cs.feature.escalation_reference() : kNaN;
  e.level_ratio = e.ratio_scale ? std::exp(cs.feature.escalation_log_ratio()) : kNaN;
  e.peak_ratio = e.ratio_scale && cs.any_active() && std::isfinite(cs.level_peak) ? std::exp(cs.level_peak) : kNaN;
  return e;
}

bool AlarmEngine::level_reached(int channel, double ratio) const {
  if (channel < 0 || channel >= impl_->channels()) throw std::invalid_argument("level_reached: channel out of range");
  return impl_->level_reached(channel, ratio);
}

}  // namespace causal::alarms
