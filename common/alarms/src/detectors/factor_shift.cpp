// Detector factor_shift (a row of the detector table, detector_table.cpp): the causal factors of a channel's
// equation left their baseline.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "../engine_internal.hpp"

namespace causal::alarms::detail {

namespace {

// ---- factor_shift: max |z| of the channel's causal factors against their baseline --------------------
DetectorReading factor_read(AlarmEngine::Impl& m, int c, const Observation& obs) {
  auto& cs = m.ch[static_cast<std::size_t>(c)];
  int monitored = 0;
  for (int i : cs.factors) monitored += m.fac[static_cast<std::size_t>(i)].monitored ? 1 : 0;
  const double stat = cs.factor_stat, thr = m.p.factor_threshold(monitored);
  // The run above the threshold (its start is the onset) is tracked whatever the latch does.
  if (std::isfinite(stat) && stat >= thr && !cs.factor_in_run) {
    cs.factor_in_run = true;
    cs.factor_run_start_index = obs.index;
    cs.factor_run_start_time_ns = obs.time_ns;
  } else if (std::isfinite(stat) && stat < thr) {
    cs.factor_in_run = false;
  }
  return {m.p.factor_enabled && monitored > 0, stat, thr};
}
void factor_onset(AlarmEngine::Impl& m, int c, const Observation&, std::uint64_t& index, std::int64_t& time_ns) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  index = cs.factor_run_start_index;
  time_ns = cs.factor_run_start_time_ns;
}
Severity factor_severity(const AlarmEngine::Impl& m, int c) {
  return severity_by_sigma(m.p, m.ch[static_cast<std::size_t>(c)].factor_stat);
}

std::string factor_describe(const AlarmEngine::Impl& m, int c, const AlarmSlot& slot, const Observation&) {
  std::ostringstream os;
  os << m.names[static_cast<std::size_t>(c)] << ": the causal factors of its equation left their baseline: max |z| "
     << fixed(slot.score, 2) << " >= " << fixed(slot.threshold, 2) << " (Bonferroni, " << general(m.p.factor_false_alarm_prob)
     << " per observation) for " << m.p.factor_persistence << "+ observations since "
     << at(slot.onset_index, slot.onset_time_ns) << ".";
  return os.str();
}

}  // namespace

DetectorKind factor_shift_detector() {
  return {kind::kFactorShift, "causal factors of the channel's equation", "max |z| against the baseline, Bonferroni",
          category::kDegradation, factor_read, factor_onset, factor_severity, factor_describe};
}

}  // namespace causal::alarms::detail
