// The detector table: every alarm kind of the engine as one row (what it watches, its statistic and
// threshold, where its change began, what severity its level calls for). AlarmEngine::observe loops over
// it; adding a kind = one row here + one file in detectors/ (its read, onset, severity and describe
// functions, returned as a DetectorKind) + its KindIndex (engine_internal.hpp).
#include <cmath>

#include "engine_internal.hpp"

namespace causal::alarms::detail {

Severity severity_by_sigma(const AlarmParams& p, double level) {
  if (!std::isfinite(level)) return Severity::Advisory;
  if (level >= p.critical_sigma) return Severity::Critical;
  if (level >= p.warning_sigma) return Severity::Warning;
  return Severity::Advisory;
}

const std::array<DetectorKind, kKindCount>& detector_table() {
  // In KindIndex order (the per-channel alarm slots).
  static const std::array<DetectorKind, kKindCount> table{{
      feature_drift_detector(),
      innovation_rise_detector(),
      innovation_nis_detector(),
      factor_shift_detector(),
  }};
  return table;
}

const char* kind_name(int kind_index) {
  return kind_index >= 0 && kind_index < kKindCount ? detector_table()[static_cast<std::size_t>(kind_index)].name : "?";
}

}  // namespace causal::alarms::detail
