// Checkpoints of AlarmEngine (crash and restart safety): the configuration first (asset group, names,
// parameters), then every piece of state that changes after construction, each in its own tagged section.
// A restore rebuilds the engine from the configuration with the normal constructor (so the derived
// structure cannot disagree with it) and then overwrites the changing state.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/estimation/state_archive.hpp"
#include "engine_internal.hpp"

namespace causal::alarms {

namespace detail {

namespace {

void save(causal::StateWriter& out, const Onset& o) {
  out.put(o.set);
  out.put(o.index);
  out.put(o.time_ns);
  out.put(o.level);
  out.put(o.evidence);
}

void restore(causal::StateReader& in, Onset& o) {
  in.read(o.set);
  in.read(o.index);
  in.read(o.time_ns);
  in.read(o.level);
  in.read(o.evidence);
}

std::size_t read_count(causal::StateReader& in, std::size_t expected, const char* what) {
  const auto n = in.get<std::uint64_t>();
  if (n != expected) {
    throw causal::StateError(std::string("checkpoint: ") + what + " count " + std::to_string(n) + ", expected " +
                             std::to_string(expected));
  }
  return static_cast<std::size_t>(n);
}

}  // namespace

void save(causal::StateWriter& out, const SignalMonitor& s) {
  out.begin("signal_monitor", 2);
  out.put(s.baseline);
  alarms::save(out, s.stats);
  out.put(s.monitored);
  out.put(s.last_value);
  out.put(s.last_z);
  out.put(s.detect_z);
  out.put(s.nis_z);
  out.put(s.scale_inflation);
  out.put(s.location_margin);
  s.cusum.save(out);
  s.level.save(out);
  out.put(s.anchor_location);
  out.put(s.refine_left);
  out.put(s.reference_location);
}

void restore(causal::StateReader& in, SignalMonitor& s) {
  in.expect("signal_monitor", 2);
  in.read(s.baseline);
  alarms::restore(in, s.stats);
  in.read(s.monitored);
  in.read(s.last_value);
  in.read(s.last_z);
  in.read(s.detect_z);
  in.read(s.nis_z);
  in.read(s.scale_inflation);
  in.read(s.location_margin);
  s.cusum.restore(in);
  s.level.restore(in);
  in.read(s.anchor_location);
  in.read(s.refine_left);
  in.read(s.reference_location);
}

void save(causal::StateWriter& out, const FactorMonitor& f) {
  out.begin("factor_monitor", 1);
  out.put(f.baseline);
  alarms::save(out, f.stats);
  out.put(f.monitored);
  out.put(f.last_value);
  out.put(f.last_std);
  out.put(f.last_z);
}

void restore(causal::StateReader& in, FactorMonitor& f) {
  in.expect("factor_monitor", 1);
  in.read(f.baseline);
  alarms::restore(in, f.stats);
  in.read(f.monitored);
  in.read(f.last_value);
  in.read(f.last_std);
  in.read(f.last_z);
}

void save(causal::StateWriter& out, const AlarmSlot& slot) {
  out.begin("alarm_slot", 2);
  slot.latch.save(out);
  out.put(slot.counter);  // alarm id counter: ids are never reused across a restart
  out.put(slot.id);
  out.put(static_cast<std::int32_t>(slot.severity));
  out.put(slot.raised_time_ns);
  out.put(slot.onset_index);
  out.put(slot.onset_time_ns);
  out.put(slot.score);
  out.put(slot.threshold);
  alarms::save(out, slot.last_event);
  out.put(slot.warning_run);
  out.put(slot.critical_run);
  out.put(slot.root);
  out.put(slot.root_confidence);
  out.put(slot.challenger);
  out.put(slot.challenger_run);
}

void restore(causal::StateReader& in, AlarmSlot& slot) {
  in.expect("alarm_slot", 2);
  slot.latch.restore(in);
  in.read(slot.counter);
  in.read(slot.id);
  const auto severity = in.get<std::int32_t>();
  if (slot.counter < 0 || severity < static_cast<int>(Severity::Advisory) ||
      severity > static_cast<int>(Severity::Critical)) {
    throw causal::StateError("checkpoint: alarm_slot '" + slot.id + "' holds an invalid counter or severity");
  }
  slot.severity = static_cast<Severity>(severity);
  in.read(slot.raised_time_ns);
  in.read(slot.onset_index);
  in.read(slot.onset_time_ns);
  in.read(slot.score);
  in.read(slot.threshold);
  alarms::restore(in, slot.last_event);
  in.read(slot.warning_run);
  in.read(slot.critical_run);
  in.read(slot.root);
  in.read(slot.root_confidence);
  in.read(slot.challenger);
  in.read(slot.challenger_run);
}

void save(causal::StateWriter& out, const ChannelState& cs) {
  out.begin("alarm_channel", 3);
  save(out, cs.feature);
  save(out, cs.innovation);
  cs.nis.save(out);
  out.put(static_cast<std::uint64_t>(cs.slots.size()));
  for (const auto& slot : cs.slots) save(out, slot);
  out.put(cs.factor_stat);
  out.put(cs.factor_argmax);
  out.put(cs.factor_run_start_index);
  out.put(cs.factor_run_start_time_ns);
  out.put(cs.factor_in_run);
  out.put(cs.rejected);
  out.put(cs.own_sum);
  out.put(cs.own_count);
  out.put(cs.baseline_from_filter);
  out.put(cs.baseline_from_nis);
  out.put(cs.excursion_obs);
  out.put(cs.excursion_sum_z);
  out.put(cs.change_counter);
  out.put(cs.size_run);
}

void restore(causal::StateReader& in, ChannelState& cs, int factor_count) {
  in.expect("alarm_channel", 3);
  restore(in, cs.feature);
  restore(in, cs.innovation);
  cs.nis.restore(in);
  read_count(in, cs.slots.size(), "alarm kinds");
  for (auto& slot : cs.slots) restore(in, slot);
  in.read(cs.factor_stat);
  in.read(cs.factor_argmax);
  if (cs.factor_argmax < -1 || cs.factor_argmax >= factor_count) {
    throw causal::StateError("checkpoint: alarm_channel refers to factor " + std::to_string(cs.factor_argmax) +
                             " of " + std::to_string(factor_count));
  }
  in.read(cs.factor_run_start_index);
  in.read(cs.factor_run_start_time_ns);
  in.read(cs.factor_in_run);
  in.read(cs.rejected);
  in.read(cs.own_sum);
  in.read(cs.own_count);
  in.read(cs.baseline_from_filter);
  in.read(cs.baseline_from_nis);
  in.read(cs.excursion_obs);
  in.read(cs.excursion_sum_z);
  in.read(cs.change_counter);
  in.read(cs.size_run);
}

void save(causal::StateWriter& out, const Episode& e) {
  out.begin("alarm_episode", 1);
  out.put(static_cast<std::uint64_t>(e.own.size()));
  for (const auto& o : e.own) save(out, o);
  out.put(static_cast<std::uint64_t>(e.departure.size()));
  for (const auto& o : e.departure) save(out, o);
}

void restore(causal::StateReader& in, Episode& e, int channels) {
  in.expect("alarm_episode", 1);
  e.reset(channels);
  read_count(in, e.own.size(), "episode onsets (own)");
  for (auto& o : e.own) restore(in, o);
  read_count(in, e.departure.size(), "episode onsets (departure)");
  for (auto& o : e.departure) restore(in, o);
}

void save(causal::StateWriter& out, const Confirmation& c) {
  out.begin("alarm_confirmation", 1);
  out.put(c.active);
  out.put(c.gap);
  out.put(c.restart);
  out.put(c.step_channel);
  out.put(c.gap_s);
  out.put(c.start_index);
  out.put(c.start_time_ns);
  out.put(c.step_onset_index);
  out.put(c.step_onset_time_ns);
  out.put(static_cast<std::uint64_t>(c.feature.size()));
  for (std::size_t i = 0; i < c.feature.size(); ++i) {
    out.put(c.feature[i]);
    out.put(c.innovation[i]);
  }
}

void restore(causal::StateReader& in, Confirmation& c, int channels) {
  in.expect("alarm_confirmation", 1);
  Confirmation r;
  in.read(r.active);
  in.read(r.gap);
  in.read(r.restart);
  in.read(r.step_channel);
  in.read(r.gap_s);
  in.read(r.start_index);
  in.read(r.start_time_ns);
  in.read(r.step_onset_index);
  in.read(r.step_onset_time_ns);
  const auto n = in.get<std::uint64_t>();
  if ((n != 0 && n != static_cast<std::uint64_t>(channels)) || r.step_channel < -1 || r.step_channel >= channels) {
    throw causal::StateError("checkpoint: alarm_confirmation does not fit " + std::to_string(channels) + " channels");
  }
  r.feature.resize(static_cast<std::size_t>(n));
  r.innovation.resize(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < n; ++i) {
    in.read(r.feature[i]);
    in.read(r.innovation[i]);
  }
  c = std::move(r);
}

}  // namespace detail

void AlarmEngine::Impl::save_state(causal::StateWriter& out) const {
  out.begin("alarm_engine_state", 2);
  out.put(seen);
  out.put(rejected);
  out.put(not_running);
  out.put(ready);
  out.put(static_cast<std::uint64_t>(ch.size()));
  for (const auto& cs : ch) detail::save(out, cs);
  out.put(static_cast<std::uint64_t>(fac.size()));
  for (const auto& f : fac) detail::save(out, f);
  detail::save(out, episode);
  out.put(baseline_times);
  out.put(median_interval_ns);
  out.put(has_last_time);
  out.put(last_time_ns);
  detail::save(out, confirm);
  out.put(discontinuities);
  out.put(operating_changes);
  out.put(stopped);
}

void AlarmEngine::Impl::restore_state(causal::StateReader& in) {
  in.expect("alarm_engine_state", 2);
  in.read(seen);
  in.read(rejected);
  in.read(not_running);
  in.read(ready);
  detail::read_count(in, ch.size(), "channel");
  for (auto& cs : ch) detail::restore(in, cs, static_cast<int>(fac.size()));
  detail::read_count(in, fac.size(), "factor");
  for (auto& f : fac) detail::restore(in, f);
  detail::restore(in, episode, channels());
  in.read(baseline_times);
  in.read(median_interval_ns);
  in.read(has_last_time);
  in.read(last_time_ns);
  detail::restore(in, confirm, channels());
  in.read(discontinuities);
  in.read(operating_changes);
  in.read(stopped);
}

void AlarmEngine::save(causal::StateWriter& out) const {
  const Impl& m = *impl_;
  out.begin("alarm_engine", 1);
  out.put(m.group);
  out.put(m.names);
  out.put(m.factor_names);
  alarms::save(out, m.p);
  m.save_state(out);
  out.begin("alarm_engine_end", 1);  // catches a reader that consumed a different number of fields
}

namespace {

AlarmEngine restore_engine(causal::StateReader& in, const AlarmParams* expected) {
  in.expect("alarm_engine", 1);
  auto group = in.get<std::string>();
  auto names = in.get<std::vector<std::string>>();
  auto factor_names = in.get<std::vector<std::string>>();
  AlarmParams saved;
  alarms::restore(in, saved);
  if (expected != nullptr) {
    const std::string diff = param_differences(saved, *expected);
    if (!diff.empty()) {
      throw causal::StateError("checkpoint of asset group '" + group +
                               "' was written with other alarm parameters (checkpoint -> configured: " + diff +
                               "); its baseline and detectors do not apply to this configuration");
    }
  }
  try {
    return AlarmEngine(std::move(group), std::move(names), std::move(factor_names), saved);
  } catch (const std::invalid_argument& e) {
    throw causal::StateError(std::string("checkpoint: invalid engine configuration: ") + e.what());
  }
}

}  // namespace

AlarmEngine AlarmEngine::restore(causal::StateReader& in, const AlarmParams& params) {
  AlarmEngine e = restore_engine(in, &params);
  e.impl_->restore_state(in);
  in.expect("alarm_engine_end", 1);
  return e;
}

AlarmEngine AlarmEngine::restore(causal::StateReader& in) {
  AlarmEngine e = restore_engine(in, nullptr);
  e.impl_->restore_state(in);
  in.expect("alarm_engine_end", 1);
  return e;
}

}  // namespace causal::alarms
