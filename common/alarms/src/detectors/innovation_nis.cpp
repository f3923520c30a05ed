// Detector innovation_nis (a row of the detector table, detector_table.cpp): the causal model no longer fits
// the channel.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "../engine_internal.hpp"

namespace causal::alarms::detail {

namespace {

// ---- innovation_nis: window mean of clipped squared standardised innovations -------------------------
DetectorReading nis_read(AlarmEngine::Impl& m, int c, const Observation&) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  return {m.p.nis_enabled && cs.innovation.monitored,
          std::isfinite(cs.innovation.last_z) && cs.nis.full() ? cs.nis.mean() : kNaN, m.nis_thr};
}
void nis_onset(AlarmEngine::Impl&, int, const Observation& obs, std::uint64_t& index, std::int64_t& time_ns) {
  index = obs.index;  // the window has no sharp change point: the raise itself
  time_ns = obs.time_ns;
}
Severity nis_severity(const AlarmEngine::Impl& m, int c) {
  const double level = m.ch[static_cast<std::size_t>(c)].innovation.level.median();
  return severity_by_sigma(m.p, m.p.nis_two_sided ? std::abs(level) : level);
}

std::string nis_describe(const AlarmEngine::Impl& m, int c, const AlarmSlot& slot, const Observation& obs) {
  const auto& p = m.p;
  std::ostringstream os;
  os << m.names[static_cast<std::size_t>(c)] << ": the causal model no longer explains this channel: mean normalised "
     << "innovation squared" << (p.nis_two_sided ? "" : " (upward departures)") << " over the last " << p.nis_window
     << " observations is " << fixed(slot.score, 2) << " (baseline " << (p.nis_two_sided ? "1" : "0.5") << ", threshold "
     << fixed(slot.threshold, 2) << " for a false-alarm probability of " << general(p.nis_false_alarm_prob)
     << " per observation), raised at " << at(obs.index, obs.time_ns) << ".";
  return os.str();
}

}  // namespace

DetectorKind innovation_nis_detector() {
  return {kind::kInnovationNis, "standardised innovation", "window mean of clipped squared upward departures",
          category::kDegradation, nis_read, nis_onset, nis_severity, nis_describe};
}

}  // namespace causal::alarms::detail
