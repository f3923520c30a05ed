// Per-signal updates of the alarm engine after the baseline (see engine_internal.hpp: update_signal).
#include <algorithm>
#include <cmath>

#include "engine_internal.hpp"

namespace causal::alarms::detail {

void update_signal(SignalMonitor& s, double v, const AlarmParams& p, const Observation& obs, bool track) {
  s.last_value = v;
  s.last_z = s.monitored && std::isfinite(v) ? s.standardize(v) : kNaN;
  s.nis_z = s.last_z / s.scale_inflation;
  s.detect_z = s.nis_z - s.location_margin;
  if (!std::isfinite(s.last_z)) return;
  // Bounded influence of one snapshot: it adds at most clip - k to the CUSUM (< h), and it moves the level
  // (median of level_window) by at most one rank, so it cannot carry the size floor either.
  s.cusum.update(s.detect_z, obs.index, obs.time_ns);
  s.level.push(s.last_z);
  // Slow healthy drift (AlarmParams::baseline_tracking_observations): followed only while nothing builds
  // up, each step limited to +-k sigma, and never further than half the size floor from where it started.
  // After a re-baseline on the short confirmation window the location is refined faster, as the running mean
  // of the next baseline_observations values (12 correlated values locate a slowly wandering level poorly),
  // within the same limits.
  double tau = p.baseline_tracking_observations;
  if (s.refine_left > 0) {
    tau = std::min(tau, static_cast<double>(p.baseline_observations - s.refine_left + p.confirmation_observations));
    --s.refine_left;
  }
  if (!track || tau <= 0.0 || s.cusum.value() > 0.0 || !std::isfinite(s.anchor_location)) return;
  const double step = std::clamp(s.last_z, -p.cusum_k, p.cusum_k) * s.stats.scale / tau;
  const double room = 0.5 * std::log(p.advisory_ratio);
  s.stats.location = std::clamp(s.stats.location + step, s.anchor_location - room, s.anchor_location + room);
}

// The wander range (SignalMonitor::wander_top): an excursion of the level over the location is learned when
// the level has come back to at most half of it (a wander returns; a degradation is monotone and persistent and
// never does) while the channel has no alarm beyond advisory, and when it rose gradually: a level that jumped by
// the size floor from one observation to the next is a step (an intermittent fault, a change of load), not a
// wander over days, and a recurrence of it must still alarm. Returns the level's log ratio over the location
// (NaN without a level).
double learn_wander(ChannelState& cs, const AlarmParams& p) {
  auto& f = cs.feature;
  const double rr = p.feature_log_transform ? f.level_log_ratio() : kNaN;
  if (!std::isfinite(rr)) {
    f.excursion_peak = kNaN;  // a new level window (re-baseline): a new excursion
    f.excursion_above = 0;
    f.excursion_last = kNaN;
    f.excursion_jumped = 0;
    return rr;
  }
  if (std::isfinite(f.excursion_last) && rr - f.excursion_last >= std::log(p.advisory_ratio)) f.excursion_jumped = 1;
  f.excursion_last = rr;
  f.excursion_peak = std::isfinite(f.excursion_peak) ? std::max(f.excursion_peak, rr) : rr;
  if (rr >= std::log(p.advisory_ratio)) ++f.excursion_above;
  const bool escalated = std::any_of(cs.slots.begin(), cs.slots.end(),
                                     [](const AlarmSlot& a) { return a.latch.active() && a.severity != Severity::Advisory; });
  if (!escalated && rr <= 0.5 * f.excursion_peak && f.excursion_above >= p.baseline_observations && !f.excursion_jumped) {
    // Capped like the healthy range (max_absorbed_ratio / sqrt(advisory_ratio)). A rise that the widened floor
    // lets reach a step's size is not absorbed as a level step (confirm_step leaves it to the detectors).
    const double cap = std::log(p.max_absorbed_ratio) - 0.5 * std::log(p.advisory_ratio);
    const double top = std::min(f.excursion_peak, cap);
    f.wander_top = std::isfinite(f.wander_top) ? std::max(f.wander_top, top) : top;
  }
  if (!escalated && rr <= 0.5 * f.excursion_peak) {  // back: a new excursion
    f.excursion_peak = rr;
    f.excursion_above = 0;
    f.excursion_jumped = 0;
  }
  return rr;
}

void update_step_run(ChannelState& cs, const AlarmParams& p) {
  auto& f = cs.feature;
  if (!std::isfinite(f.last_z)) return;
  const double r = f.level_log_ratio();
  // The healthy range keeps learning for its first days while the channel has no alarm (its wander over
  // days), never beyond max_absorbed_ratio / sqrt(advisory_ratio) over the location.
  if (f.range_left > 0) {
    --f.range_left;
    if (!cs.any_active() && std::isfinite(r) && std::isfinite(f.healthy_top))
      f.healthy_top = std::max(f.healthy_top, std::min(r, std::log(p.max_absorbed_ratio) - 0.5 * std::log(p.advisory_ratio)));
  }
  const double half_floor = 0.5 * std::log(p.advisory_ratio);
  const double rr = learn_wander(cs, p);
  // The size floor: at least advisory_ratio over the baseline AND half the floor above the healthy range's top
  // (a level the channel already showed while healthy is no degradation, however it compares with a baseline
  // learned in a low stretch) AND half the floor above the top of the wander it came back from.
  const bool above_range = (!std::isfinite(f.healthy_top) || r >= f.healthy_top + half_floor) &&
                           (!std::isfinite(f.wander_top) || !std::isfinite(rr) || rr >= f.wander_top + half_floor);
  cs.size_run = std::isfinite(r) && r >= std::log(p.advisory_ratio) && above_range ? cs.size_run + 1 : 0;
  if (p.feature_log_transform && f.last_z * f.stats.scale >= std::log(p.operating_step_ratio)) {
    ++cs.excursion_obs;
    cs.excursion_sum_z += f.last_z;
  } else {
    cs.excursion_obs = 0;
    cs.excursion_sum_z = 0.0;
  }
}

bool size_matters(const AlarmEngine::Impl& m, int c) {
  const auto& f = m.ch[static_cast<std::size_t>(c)].feature;
  if (m.p.advisory_ratio <= 1.0 || !m.p.feature_log_transform || !f.monitored) return true;  // no floor / no ratio scale
  // A level that holds for level_window observations: a healthy excursion that touches the floor (a daily
  // high on top of a load swing) is not enough; a fault stays there.
  return !std::isfinite(f.level_log_ratio()) || m.ch[static_cast<std::size_t>(c)].size_run >= m.p.level_window;
}

void update_level_event(AlarmEngine::Impl& m, int c) {
  auto& cs = m.ch[static_cast<std::size_t>(c)];
  const double r = cs.feature.escalation_log_ratio();
  if (std::isfinite(r)) {
    cs.recent_ratio.push_back(r);
    if (cs.recent_ratio.size() > static_cast<std::size_t>(m.p.escalation_persistence)) cs.recent_ratio.erase(cs.recent_ratio.begin());
  }
  // Held for escalation_persistence observations = the minimum of the last ones once there are that many.
  const double held = cs.recent_ratio.size() == static_cast<std::size_t>(m.p.escalation_persistence)
                          ? *std::min_element(cs.recent_ratio.begin(), cs.recent_ratio.end())
                          : kNaN;
  if (!cs.any_active() || !std::isfinite(cs.level_peak))
    cs.level_peak = held;
  else if (std::isfinite(held))
    cs.level_peak = std::max(cs.level_peak, held);
}

double healthy_range_top(const std::vector<double>& warmup, const std::vector<double>& baseline, int window) {
  std::vector<double> all;
  for (const auto* v : {&warmup, &baseline})
    for (double x : *v)
      if (std::isfinite(x)) all.push_back(x);
  double top = kNaN;
  const auto w = static_cast<std::size_t>(std::max(window, 1));
  for (std::size_t i = 0; i + w <= all.size(); ++i) {
    const double med = median(std::vector<double>(all.begin() + static_cast<std::ptrdiff_t>(i),
                                                   all.begin() + static_cast<std::ptrdiff_t>(i + w)));
    if (!std::isfinite(top) || med > top) top = med;
  }
  return top;
}

}  // namespace causal::alarms::detail
