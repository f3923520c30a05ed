// Detector feature_drift (a row of the detector table, detector_table.cpp): the condition feature rose above
// its baseline.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "../engine_internal.hpp"

namespace causal::alarms::detail {

namespace {

// ---- feature_drift: clipped CUSUM on the standardised (log) condition feature -----------------------
// Escalation follows the failure: a level at warning_ratio x its reference (AlarmParams::max_absorbed_ratio)
// is evidence on its own (a doubling of the median of 5 is no noise), whatever a step or gap rule did to the
// CUSUM before: the statistic is then at least the threshold, so the alarm is raised and cannot clear.
DetectorReading feature_read(AlarmEngine::Impl& m, int c, const Observation&) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  double stat = std::isfinite(cs.feature.last_z) ? cs.feature.cusum.value() : kNaN;
  const double ratio = cs.feature.escalation_log_ratio();
  if (std::isfinite(stat) && m.p.feature_log_transform && std::isfinite(ratio) && ratio >= std::log(m.p.warning_ratio))
    stat = std::max(stat, m.h);
  return {m.p.feature_enabled && cs.feature.monitored, stat, m.h};
}
void feature_onset(AlarmEngine::Impl& m, int c, const Observation&, std::uint64_t& index, std::int64_t& time_ns) {
  auto& cs = m.ch[static_cast<std::size_t>(c)];
  index = cs.feature.cusum.onset_index();
  time_ns = cs.feature.cusum.onset_time_ns();
  m.episode.departure[static_cast<std::size_t>(c)].take_earlier(index, time_ns, cs.feature.level.median(),
                                                                cs.own_evidence());
}
Severity feature_severity(const AlarmEngine::Impl& m, int c) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  const double level = cs.feature.level.median();
  if (!m.p.feature_log_transform) return severity_by_sigma(m.p, level);
  if (!std::isfinite(level)) return Severity::Advisory;
  // Physical ratio of the current level to the reference (the lower of the baseline median and the level
  // before any step the engine followed; AlarmParams::max_absorbed_ratio).
  const double ratio = std::exp(cs.feature.escalation_log_ratio());
  if (ratio >= m.p.critical_ratio) return Severity::Critical;
  if (ratio >= m.p.warning_ratio) return Severity::Warning;
  return Severity::Advisory;
}

std::string feature_describe(const AlarmEngine::Impl& m, int c, const AlarmSlot& slot, const Observation&) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  const auto& p = m.p;
  const std::string& name = m.names[static_cast<std::size_t>(c)];
  std::ostringstream os;
  const double level = cs.feature.level.median();
  const double now_z = cs.feature.last_z;
  if (p.feature_log_transform) {
    const double ratio_now = std::exp(cs.feature.last_value - cs.feature.stats.location);
    const double ratio_level = std::exp(level * cs.feature.stats.scale);
    os << name << ": condition level " << general(std::exp(cs.feature.last_value)) << " is "
       << signed_fixed(100.0 * (ratio_now - 1.0), 1) << " % (" << signed_fixed(20.0 * std::log10(ratio_now), 1)
       << " dB, " << signed_fixed(now_z, 1) << " baseline sigma) above its healthy baseline median "
       << general(std::exp(cs.feature.stats.location)) << " (median of the last " << p.level_window << ": "
       << signed_fixed(100.0 * (ratio_level - 1.0), 1) << " %)";
  } else {
    os << name << ": condition level " << general(cs.feature.last_value) << " is " << signed_fixed(now_z, 1)
       << " baseline sigma above its healthy baseline median " << general(cs.feature.stats.location)
       << " (median of the last " << p.level_window << ": " << signed_fixed(level, 1) << " sigma)";
  }
  os << "; CUSUM " << fixed(slot.score, 2) << " >= " << fixed(slot.threshold, 2) << " (designed for 1 false alarm per "
     << general(p.target_arl0) << " observations); the rise began at " << at(slot.onset_index, slot.onset_time_ns) << ".";
  return os.str();
}

}  // namespace

DetectorKind feature_drift_detector() {
  return {kind::kFeatureDrift, "condition feature (log)", "clipped one-sided CUSUM of the baseline-standardised value",
          category::kDegradation, feature_read, feature_onset, feature_severity, feature_describe};
}

}  // namespace causal::alarms::detail
