// The detector table: every alarm kind of the engine as one row (what it watches, its statistic and
// threshold, where its change began, what severity its level calls for). AlarmEngine::observe loops over
// it; adding a kind = one row + its three functions here + its KindIndex (engine_internal.hpp).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "engine_internal.hpp"

namespace causal::alarms::detail {

namespace {

Severity by_sigma(const AlarmParams& p, double level) {
  if (!std::isfinite(level)) return Severity::Advisory;
  if (level >= p.critical_sigma) return Severity::Critical;
  if (level >= p.warning_sigma) return Severity::Warning;
  return Severity::Advisory;
}

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
  if (!m.p.feature_log_transform) return by_sigma(m.p, level);
  if (!std::isfinite(level)) return Severity::Advisory;
  // Physical ratio of the current level to the reference (the lower of the baseline median and the level
  // before any step the engine followed; AlarmParams::max_absorbed_ratio).
  const double ratio = std::exp(cs.feature.escalation_log_ratio());
  if (ratio >= m.p.critical_ratio) return Severity::Critical;
  if (ratio >= m.p.warning_ratio) return Severity::Warning;
  return Severity::Advisory;
}

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

Severity innovation_severity(const AlarmEngine::Impl& m, int c) {
  return by_sigma(m.p, m.ch[static_cast<std::size_t>(c)].innovation.level.median());  // upward departures only
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
  return by_sigma(m.p, m.p.nis_two_sided ? std::abs(level) : level);
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
  return by_sigma(m.p, m.ch[static_cast<std::size_t>(c)].factor_stat);
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

const std::array<DetectorKind, kKindCount>& detector_table() {
  static const std::array<DetectorKind, kKindCount> table{{
      {kind::kFeatureDrift, "condition feature (log)", "clipped one-sided CUSUM of the baseline-standardised value",
       category::kDegradation, feature_read, feature_onset, feature_severity, feature_describe},
      {kind::kInnovationRise, "standardised innovation (or log mean NIS)", "clipped one-sided CUSUM",
       category::kDegradation, innovation_read, innovation_onset, innovation_severity, innovation_describe},
      {kind::kInnovationNis, "standardised innovation", "window mean of clipped squared upward departures",
       category::kDegradation, nis_read, nis_onset, nis_severity, nis_describe},
      {kind::kFactorShift, "causal factors of the channel's equation", "max |z| against the baseline, Bonferroni",
       category::kDegradation, factor_read, factor_onset, factor_severity, factor_describe},
  }};
  return table;
}

const char* kind_name(int kind_index) {
  return kind_index >= 0 && kind_index < kKindCount ? detector_table()[static_cast<std::size_t>(kind_index)].name : "?";
}

}  // namespace causal::alarms::detail
