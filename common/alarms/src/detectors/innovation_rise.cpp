// Detector innovation_rise (a row of the detector table, detector_table.cpp): the part of a channel the others
// do not explain rose: its own behaviour changed.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "../engine_internal.hpp"

namespace causal::alarms::detail {

namespace {

// ---- innovation_rise: the same CUSUM on the standardised innovation (own behaviour) -----------------
DetectorReading innovation_read(AlarmEngine::Impl& m, int c, const Observation&) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  return {m.p.innovation_enabled && cs.innovation.monitored,
          std::isfinite(cs.innovation.last_z) ? cs.innovation.cusum.value() : kNaN, m.h};
}
void innovation_onset(AlarmEngine::Impl& m, int c, const Observation&, std::uint64_t& index, std::int64_t& time_ns) {
  auto& cs = m.ch[static_cast<std::size_t>(c)];
  index = cs.innovation.cusum.onset_index();
  time_ns = cs.innovation.cusum.onset_time_ns();
  m.episode.own[static_cast<std::size_t>(c)].take_earlier(index, time_ns, cs.innovation.level.median());
}

Severity innovation_severity(const AlarmEngine::Impl& m, int c) {
  return severity_by_sigma(m.p, m.ch[static_cast<std::size_t>(c)].innovation.level.median());  // upward departures only
}

std::string innovation_describe(const AlarmEngine::Impl& m, int c, const AlarmSlot& slot, const Observation&) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  std::ostringstream os;
  os << m.names[static_cast<std::size_t>(c)] << ": the part of its signal that the other channels do not explain is now "
     << signed_fixed(cs.innovation.last_z, 1) << " baseline sigma (median of the last " << m.p.level_window << ": "
     << signed_fixed(cs.innovation.level.median(), 1) << "); CUSUM " << fixed(slot.score, 2) << " >= "
     << fixed(slot.threshold, 2) << " (1 false alarm per " << general(m.p.target_arl0)
     << " observations): its own behaviour changed, starting at " << at(slot.onset_index, slot.onset_time_ns) << ".";
  return os.str();
}

}  // namespace

DetectorKind innovation_rise_detector() {
  return {kind::kInnovationRise, "standardised innovation (or log mean NIS)", "clipped one-sided CUSUM",
          category::kDegradation, innovation_read, innovation_onset, innovation_severity, innovation_describe};
}

}  // namespace causal::alarms::detail
