// Gaps and operating changes (AlarmParams::confirmation_observations): a discontinuity or an abrupt, large
// step puts the asset group under confirmation; at the end of the window each channel is re-baselined (an
// operating change, reported as such) or judged by the detectors as before (degradation).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "engine_internal.hpp"
#include "causal/io/time_format.hpp"

namespace causal::alarms {

namespace {

// Theil-Sen slope (median of the pairwise slopes) of the finite values against their position: robust to
// a few outliers, which a 12-value window of vibration levels may hold. NaN with fewer than 3 values.
double theil_sen_slope(const std::vector<double>& v) {
  std::vector<double> slopes;
  int finite = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) continue;
    ++finite;
    for (std::size_t j = i + 1; j < v.size(); ++j)
      if (std::isfinite(v[j])) slopes.push_back((v[j] - v[i]) / static_cast<double>(j - i));
  }
  return finite >= 3 ? median(slopes) : detail::kNaN;
}

std::string fixed(double v, int decimals, bool sign = false) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << (sign ? std::showpos : std::noshowpos) << v;
  return os.str();
}

std::string duration(double s) {
  if (s >= 86400.0) return fixed(s / 86400.0, 1) + " days";
  if (s >= 3600.0) return fixed(s / 3600.0, 1) + " h";
  return fixed(s / 60.0, 1) + " min";
}

// Back to its (new) baseline: CUSUM, level window and own-change evidence restart.
void restart(detail::SignalMonitor& s) {
  s.cusum.reset();
  s.level.reset();
}

// A gap's common step: the median, over the channels re-baselined at it (settled, no open alarm), of their
// level change across the gap (window median against the location before it). Each channel's reference
// becomes its level before the gap plus its own step, but never more than the common one: the severities stay
// judged against the healthy level re-levelled as the machine was, never against a level that already holds
// one channel's wear (AlarmParams::max_absorbed_ratio). NaN when none.
double gap_common_step(const AlarmEngine::Impl& m) {
  std::vector<double> steps;
  const int w = m.p.confirmation_observations;
  for (int c = 0; c < m.channels(); ++c) {
    const auto& cs = m.ch[static_cast<std::size_t>(c)];
    const auto& fv = m.confirm.feature[static_cast<std::size_t>(c)];
    const double rise = theil_sen_slope(fv) * (w - 1) / cs.feature.stats.scale;
    const double step = median(fv) - cs.feature.stats.location;
    if (!cs.any_active() && cs.feature.monitored && std::isfinite(rise) && rise < m.p.settle_trend_sigma && std::isfinite(step))
      steps.push_back(step);
  }
  return steps.empty() ? detail::kNaN : median(steps);
}

// The reference of channel c after a gap: its level before the gap plus its own step, at most the common one.
double gap_reference(const AlarmEngine::Impl& m, int c, double common_step) {
  const auto& cs = m.ch[static_cast<std::size_t>(c)];
  const double own = median(m.confirm.feature[static_cast<std::size_t>(c)]) - cs.feature.stats.location;
  return std::isfinite(own) && std::isfinite(common_step) ? cs.feature.stats.location + std::min(own, common_step) : detail::kNaN;
}

}  // namespace

bool AlarmEngine::Impl::is_discontinuity(const Observation& obs, std::uint64_t lost) const {
  // After lost observations the source (or the estimator, which flags the first vector after a loss so no lag
  // spans it) marks a discontinuity of the twin's input, not of the machine; their time is no recording gap.
  if (obs.discontinuity && lost == 0) return true;
  if (!has_last_time || median_interval_ns <= 0.0) return false;
  return static_cast<double>(obs.time_ns - last_time_ns) >
         p.gap_multiple * median_interval_ns * static_cast<double>(lost + 1);
}

int AlarmEngine::Impl::abrupt_step() const {
  if (!p.feature_enabled || !p.feature_log_transform) return -1;
  int best = -1;
  double best_ratio = 0.0;
  for (int c = 0; c < channels(); ++c) {
    const auto& cs = ch[static_cast<std::size_t>(c)];
    if (!cs.feature.monitored || cs.slots[detail::kFeature].latch.active()) continue;
    // At least 2 observations at the step's size (one is a spike), at most onset_tolerance + 1 (abrupt).
    if (cs.feature.cusum.value() < h || cs.excursion_obs < 2 || cs.excursion_obs > p.onset_tolerance + 1) continue;
    const double ratio = std::exp(cs.excursion_sum_z / cs.excursion_obs * cs.feature.stats.scale);
    if (ratio >= p.operating_step_ratio && ratio > best_ratio) {
      best = c;
      best_ratio = ratio;
    }
  }
  return best;
}

void AlarmEngine::Impl::start_confirmation(const Observation& obs, bool gap, int step_channel, double gap_s) {
  confirm.reset();
  confirm.active = true;
  confirm.gap = gap;
  confirm.step_channel = step_channel;
  confirm.gap_s = gap_s;
  confirm.start_index = obs.index;
  confirm.start_time_ns = obs.time_ns;
  if (step_channel >= 0) {
    const auto& cusum = ch[static_cast<std::size_t>(step_channel)].feature.cusum;
    confirm.step_onset_index = cusum.onset_index();
    confirm.step_onset_time_ns = cusum.onset_time_ns();
  }
  confirm.feature.assign(ch.size(), {});
  confirm.innovation.assign(ch.size(), {});
}

std::vector<bool> AlarmEngine::Impl::settled_steps() const {
  std::vector<bool> moved(ch.size(), false);
  if (confirm.gap) return moved;
  const int w = p.confirmation_observations;
  for (int c = 0; c < channels(); ++c) {
    const auto& cs = ch[static_cast<std::size_t>(c)];
    const auto& fv = confirm.feature[static_cast<std::size_t>(c)];
    const double rise = theil_sen_slope(fv) * (w - 1) / cs.feature.stats.scale;
    const double new_loc = median(fv);
    // The step's channel too must have settled at a step's size: a smaller rise that only looked abrupt on
    // a noisy observation or two is left to the detectors (it is not absorbed).
    moved[static_cast<std::size_t>(c)] = std::isfinite(rise) && rise < p.settle_trend_sigma && std::isfinite(new_loc) &&
                                         (c == confirm.step_channel || !cs.any_active()) && cs.feature.monitored &&
                                         std::abs(new_loc - cs.feature.stats.location) >= std::log(p.operating_step_ratio);
  }
  return moved;
}

void AlarmEngine::Impl::raise_unconfirmed_step(int c, const Observation& obs, const std::string& why,
                                               std::vector<AlarmEvent>& events) {
  auto& cs = ch[static_cast<std::size_t>(c)];
  cs.slots[detail::kFeature].latch.force_raise();
  begin_alarm(c, detail::kFeature, obs);
  auto& slot = cs.slots[detail::kFeature];
  slot.score = cs.feature.cusum.value();
  slot.threshold = h;
  slot.root = root_cause(c, slot.onset_index);
  slot.root_confidence = attribution_confidence(slot.root, departed_evidence());
  AlarmEvent e = make_event(c, detail::kFeature, AlarmState::Raised, obs);
  e.reason = why + e.reason;
  slot.last_event = e;
  events.push_back(std::move(e));
}

void AlarmEngine::Impl::emit_change(int c, const char* kind_name, const std::string& why, const Observation& obs,
                                    std::vector<AlarmEvent>& events) {
  auto& cs = ch[static_cast<std::size_t>(c)];
  ++cs.change_counter;
  ++operating_changes;
  AlarmEvent e;
  e.alarm_id = alarm_id(c, kind_name, cs.change_counter);
  e.channel = c;
  e.kind = kind_name;
  e.category = category::kOperatingChange;
  e.state = AlarmState::Raised;
  e.raised_time_ns = obs.time_ns;
  e.index = obs.index;
  e.onset_index = confirm.step_channel == c ? confirm.step_onset_index : confirm.start_index;
  e.onset_time_ns = confirm.step_channel == c ? confirm.step_onset_time_ns : confirm.start_time_ns;
  e.root_cause_channel = c;
  e.root_cause_confidence = 1.0;
  e.reason = why;
  events.push_back(e);
  // A point event: raised and cleared at once, so a last-value reader never shows it as active.
  e.state = AlarmState::Cleared;
  e.cleared_time_ns = obs.time_ns;
  events.push_back(std::move(e));
}

void AlarmEngine::Impl::confirm_step(const Observation& obs, const std::vector<double>& feat,
                                     const std::vector<double>& innov, std::vector<AlarmEvent>& events) {
  for (std::size_t c = 0; c < ch.size(); ++c) {
    confirm.feature[c].push_back(feat[c]);
    confirm.innovation[c].push_back(innov[c]);
  }
  if (static_cast<int>(confirm.feature[0].size()) < p.confirmation_observations) return;

  const int w = p.confirmation_observations;
  // new_reference: a gap / restart or a machine-wide operating change moves the escalation reference too
  // (the new reference, log level); a single channel's step does not (NaN; AlarmParams::max_absorbed_ratio).
  auto rebaseline = [&](int c, double new_reference) {
    auto& cs = ch[static_cast<std::size_t>(c)];
    const double f = median(confirm.feature[static_cast<std::size_t>(c)]);
    if (cs.feature.monitored && std::isfinite(f)) cs.feature.stats.location = f;
    cs.feature.anchor_location = cs.feature.stats.location;
    cs.feature.refine_left = p.baseline_observations;
    if (std::isfinite(new_reference) || !std::isfinite(cs.feature.reference_location))
      cs.feature.reference_location = std::isfinite(new_reference) ? new_reference : cs.feature.stats.location;
    restart(cs.feature);
    cs.own_sum = 0.0;
    cs.own_count = 0;
    cs.excursion_obs = 0;
    cs.excursion_sum_z = 0.0;
    cs.size_run = 0;
  };
  // Innovations carry a level change until the filter's factors adapt: their location is re-learned
  // upwards only (see AlarmParams::settle_trend_sigma), for every channel without an active alarm.
  auto relearn_innovation = [&](int c) {
    auto& cs = ch[static_cast<std::size_t>(c)];
    const double v = median(confirm.innovation[static_cast<std::size_t>(c)]);
    if (cs.innovation.monitored && std::isfinite(v) && v > cs.innovation.stats.location) cs.innovation.stats.location = v;
    restart(cs.innovation);
    cs.nis.reset();
  };
  auto emit = [&](int c, const char* kind_name, const std::string& why) { emit_change(c, kind_name, why, obs, events); };

  const double common_step = confirm.gap ? gap_common_step(*this) : detail::kNaN;

  const std::string when = "observation " + std::to_string(confirm.start_index) + " (" +
                           io::format_utc_seconds(confirm.start_time_ns) + ")";
  // Channels whose level moved by a step at least operating_step_ratio in the window and settled;
  // machine-wide when they are at least two and at least half the channels.
  const std::vector<bool> moved = settled_steps();
  const int moved_count = static_cast<int>(std::count(moved.begin(), moved.end(), true));
  const bool machine_wide = moved_count >= 2 && 2 * moved_count >= channels();
  for (int c = 0; c < channels(); ++c) {
    auto& cs = ch[static_cast<std::size_t>(c)];
    const auto& fv = confirm.feature[static_cast<std::size_t>(c)];
    const double scale = cs.feature.stats.scale;
    const double rise = theil_sen_slope(fv) * (w - 1) / scale;  // baseline sigmas across the window
    const bool settled = std::isfinite(rise) && rise < p.settle_trend_sigma;
    const double old_loc = cs.feature.stats.location, new_loc = median(fv);
    const double pct = 100.0 * (std::exp(new_loc - old_loc) - 1.0);
    const std::string& name = names[static_cast<std::size_t>(c)];
    const std::string trend = "it moved " + fixed(std::isfinite(rise) ? rise : 0.0, 1, true) + " baseline sigma across the " +
                              std::to_string(w) + " observations (settled below " + fixed(p.settle_trend_sigma, 1) + ")";
    if (confirm.gap) {
      if (cs.any_active() || !settled || !cs.feature.monitored) continue;  // judged by the detectors as before
      const std::string gap = confirm.restart       ? "a stop (every channel far below its baseline)"
                              : confirm.gap_s > 0.0 ? "a gap of " + duration(confirm.gap_s) + " (more than " +
                                                          fixed(p.gap_multiple, 1) + " x the usual interval of " +
                                                          duration(median_interval_ns * 1e-9) + ")"
                                                    : "a discontinuity or declared operating change flagged by the source";
      emit(c, kind::kDiscontinuity,
           name + ": the recording resumed after " + gap + " at " + when + "; its level is " + fixed(pct, 1, true) +
               " % against the old baseline and " + trend + ": re-baselined on the " + std::to_string(w) +
               " observations after the gap (not a fault; alarms judge changes from the new level).");
      rebaseline(c, gap_reference(*this, c, common_step));
      relearn_innovation(c);
    } else if (moved[static_cast<std::size_t>(c)] || (c == confirm.step_channel && !settled)) {
      // The step's channel, and any other channel whose level moved by a step as large in the same window.
      // Settled and machine-wide (at least half the channels: a change of load or speed moves the machine
      // as a whole) -> a confirmed operating change, new reference. Settled on fewer channels -> followed as
      // a level step while within max_absorbed_ratio of its reference. Still rising, or a step beyond that
      // limit -> the step's channel alarms, the others are left to their detectors.
      const double over_reference = new_loc - cs.feature.reference_location;
      const bool absorbable = machine_wide || over_reference <= std::log(p.max_absorbed_ratio);
      if ((!settled || !absorbable) && c != confirm.step_channel) continue;
      // A range widened by a returned wander (wander_top) lifts the floor past a step's size: a slow rise would
      // be absorbed here before it may alarm. Left to its detectors unless the machine moved (alarm-rules.md 9).
      if (settled && !machine_wide && std::isfinite(cs.feature.wander_top)) continue;
      if (!settled || !absorbable) {  // the alarm the step would have raised, raised now with its onset
        raise_unconfirmed_step(
            c, obs,
            "Abrupt rise at " + when +
                (settled ? " settled on this channel alone at " + fixed(100.0 * (std::exp(over_reference) - 1.0), 1, true) +
                               " % over its reference, beyond the " + fixed(100.0 * (p.max_absorbed_ratio - 1.0), 0) +
                               " % a single channel may step without the machine: degradation, not an operating change. "
                         : " did not settle: " + trend + ": progressive, not an operating change. "),
            events);
        continue;
      }
      const std::string with = c == confirm.step_channel ? "" : " (with " + names[static_cast<std::size_t>(confirm.step_channel)] + ")";
      if (machine_wide) {
        emit(c, kind::kOperatingChange,
             name + ": operating change: its level stepped " + fixed(pct, 1, true) + " % at once at " + when + with +
                 ", " + std::to_string(moved_count) + " of " + std::to_string(channels()) + " channels moved, and " + trend +
                 ": re-baselined at the new level (a change of load or speed, not a fault; alarms judge changes from "
                 "the new level).");
      } else {
        emit(c, kind::kLevelStep,
             name + ": level step of " + fixed(pct, 1, true) + " % at " + when + with + " that " + trend + "; only " +
                 std::to_string(moved_count) + " of " + std::to_string(channels()) +
                 " channels moved, so it is not confirmed as an operating change: followed from the new level (" +
                 fixed(100.0 * (std::exp(over_reference) - 1.0), 1, true) + " % over its reference, limit " +
                 fixed(100.0 * (p.max_absorbed_ratio - 1.0), 0, true) +
                 " %); warning and critical are still judged against the reference.");
      }
      rebaseline(c, machine_wide ? median(fv) : detail::kNaN);
    }
  }
  if (!confirm.gap && std::find_if(events.begin(), events.end(), [](const AlarmEvent& e) {
                        return e.category == category::kOperatingChange;
                      }) != events.end()) {
    for (int c = 0; c < channels(); ++c)
      if (!ch[static_cast<std::size_t>(c)].any_active()) relearn_innovation(c);
  }
  confirm.reset();
}

}  // namespace causal::alarms
