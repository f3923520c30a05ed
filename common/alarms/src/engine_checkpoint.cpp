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
#include "causal/estimation/state_fields.hpp"
#include "engine_internal.hpp"

namespace causal::alarms {

namespace detail {

namespace {

// The field lists (SaveFields / RestoreFields, state_fields.hpp): O is the structure, const when saving.
template <class Io, class O>
void onset_fields(Io io, O& o) {
  io(o.set);
  io(o.index);
  io(o.time_ns);
  io(o.level);
  io(o.evidence);
}

template <class Io, class S>
void signal_fields(Io io, S& s) {
  io(s.baseline);
  io.section(s.stats);
  io(s.monitored);
  io(s.last_value);
  io(s.last_z);
  io(s.detect_z);
  io(s.nis_z);
  io(s.scale_inflation);
  io(s.location_margin);
  io.object(s.cusum);
  io.object(s.level);
  io(s.anchor_location);
  io(s.refine_left);
  io(s.reference_location);
  io(s.warmup);
  io(s.healthy_top);
  io(s.range_left);
  io(s.wander_top);
  io(s.excursion_peak);
  io(s.excursion_above);
  io(s.excursion_last);
  io(s.excursion_jumped);
}

template <class Io, class F>
void factor_fields(Io io, F& f) {
  io(f.baseline);
  io.section(f.stats);
  io(f.monitored);
  io(f.last_value);
  io(f.last_std);
  io(f.last_z);
}

// An alarm slot's fields before and after its severity (written as an int32, checked on restore).
template <class Io, class A>
void slot_fields_before_severity(Io io, A& slot) {
  io.object(slot.latch);
  io(slot.counter);  // alarm id counter: ids are never reused across a restart
  io(slot.id);
}

template <class Io, class A>
void slot_fields_after_severity(Io io, A& slot) {
  io(slot.raised_time_ns);
  io(slot.onset_index);
  io(slot.onset_time_ns);
  io(slot.score);
  io(slot.threshold);
  io.section(slot.last_event);
  io(slot.warning_run);
  io(slot.critical_run);
  io(slot.root);
  io(slot.root_confidence);
  io(slot.challenger);
  io(slot.challenger_run);
}

// A channel's fields after its factor_argmax (checked on restore).
template <class Io, class C>
void channel_fields_after_argmax(Io io, C& cs) {
  io(cs.factor_run_start_index);
  io(cs.factor_run_start_time_ns);
  io(cs.factor_in_run);
  io(cs.rejected);
  io(cs.own_sum);
  io(cs.own_count);
  io(cs.baseline_from_filter);
  io(cs.baseline_from_nis);
  io(cs.excursion_obs);
  io(cs.excursion_sum_z);
  io(cs.change_counter);
  io(cs.size_run);
  io(cs.recent_ratio);
  io(cs.level_peak);
}

template <class Io, class C>
void confirmation_scalars(Io io, C& c) {
  io(c.active);
  io(c.gap);
  io(c.restart);
  io(c.step_channel);
  io(c.gap_s);
  io(c.start_index);
  io(c.start_time_ns);
  io(c.step_onset_index);
  io(c.step_onset_time_ns);
}

void save(estimation::StateWriter& out, const Onset& o) { onset_fields(estimation::SaveFields{out}, o); }
void restore(estimation::StateReader& in, Onset& o) { onset_fields(estimation::RestoreFields{in}, o); }

std::size_t read_count(estimation::StateReader& in, std::size_t expected, const char* what) {
  const auto n = in.get<std::uint64_t>();
  if (n != expected) {
    throw estimation::StateError(std::string("checkpoint: ") + what + " count " + std::to_string(n) + ", expected " +
                             std::to_string(expected));
  }
  return static_cast<std::size_t>(n);
}

}  // namespace

void save(estimation::StateWriter& out, const SignalMonitor& s) {
  out.begin("signal_monitor", 4);
  signal_fields(estimation::SaveFields{out}, s);
}

void restore(estimation::StateReader& in, SignalMonitor& s) {
  in.expect("signal_monitor", 4);
  signal_fields(estimation::RestoreFields{in}, s);
}

void save(estimation::StateWriter& out, const FactorMonitor& f) {
  out.begin("factor_monitor", 1);
  factor_fields(estimation::SaveFields{out}, f);
}

void restore(estimation::StateReader& in, FactorMonitor& f) {
  in.expect("factor_monitor", 1);
  factor_fields(estimation::RestoreFields{in}, f);
}

void save(estimation::StateWriter& out, const AlarmSlot& slot) {
  out.begin("alarm_slot", 2);
  slot_fields_before_severity(estimation::SaveFields{out}, slot);
  out.put(static_cast<std::int32_t>(slot.severity));
  slot_fields_after_severity(estimation::SaveFields{out}, slot);
}

void restore(estimation::StateReader& in, AlarmSlot& slot) {
  in.expect("alarm_slot", 2);
  slot_fields_before_severity(estimation::RestoreFields{in}, slot);
  const auto severity = in.get<std::int32_t>();
  if (slot.counter < 0 || severity < static_cast<int>(Severity::Advisory) ||
      severity > static_cast<int>(Severity::Critical)) {
    throw estimation::StateError("checkpoint: alarm_slot '" + slot.id + "' holds an invalid counter or severity");
  }
  slot.severity = static_cast<Severity>(severity);
  slot_fields_after_severity(estimation::RestoreFields{in}, slot);
}

void save(estimation::StateWriter& out, const ChannelState& cs) {
  out.begin("alarm_channel", 4);
  save(out, cs.feature);
  save(out, cs.innovation);
  cs.nis.save(out);
  out.put(static_cast<std::uint64_t>(cs.slots.size()));
  for (const auto& slot : cs.slots) save(out, slot);
  out.put(cs.factor_stat);
  out.put(cs.factor_argmax);
  channel_fields_after_argmax(estimation::SaveFields{out}, cs);
}

void restore(estimation::StateReader& in, ChannelState& cs, int factor_count) {
  in.expect("alarm_channel", 4);
  restore(in, cs.feature);
  restore(in, cs.innovation);
  cs.nis.restore(in);
  read_count(in, cs.slots.size(), "alarm kinds");
  for (auto& slot : cs.slots) restore(in, slot);
  in.read(cs.factor_stat);
  in.read(cs.factor_argmax);
  if (cs.factor_argmax < -1 || cs.factor_argmax >= factor_count) {
    throw estimation::StateError("checkpoint: alarm_channel refers to factor " + std::to_string(cs.factor_argmax) +
                             " of " + std::to_string(factor_count));
  }
  channel_fields_after_argmax(estimation::RestoreFields{in}, cs);
}

void save(estimation::StateWriter& out, const Episode& e) {
  out.begin("alarm_episode", 1);
  out.put(static_cast<std::uint64_t>(e.own.size()));
  for (const auto& o : e.own) save(out, o);
  out.put(static_cast<std::uint64_t>(e.departure.size()));
  for (const auto& o : e.departure) save(out, o);
}

void restore(estimation::StateReader& in, Episode& e, int channels) {
  in.expect("alarm_episode", 1);
  e.reset(channels);
  read_count(in, e.own.size(), "episode onsets (own)");
  for (auto& o : e.own) restore(in, o);
  read_count(in, e.departure.size(), "episode onsets (departure)");
  for (auto& o : e.departure) restore(in, o);
}

void save(estimation::StateWriter& out, const Confirmation& c) {
  out.begin("alarm_confirmation", 1);
  confirmation_scalars(estimation::SaveFields{out}, c);
  out.put(static_cast<std::uint64_t>(c.feature.size()));
  for (std::size_t i = 0; i < c.feature.size(); ++i) {
    out.put(c.feature[i]);
    out.put(c.innovation[i]);
  }
}

void restore(estimation::StateReader& in, Confirmation& c, int channels) {
  in.expect("alarm_confirmation", 1);
  Confirmation r;
  confirmation_scalars(estimation::RestoreFields{in}, r);
  const auto n = in.get<std::uint64_t>();
  if ((n != 0 && n != static_cast<std::uint64_t>(channels)) || r.step_channel < -1 || r.step_channel >= channels) {
    throw estimation::StateError("checkpoint: alarm_confirmation does not fit " + std::to_string(channels) + " channels");
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

void AlarmEngine::Impl::save_state(estimation::StateWriter& out) const {
  out.begin("alarm_engine_state", 3);
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
  detail::save(out, continuity);
}

void AlarmEngine::Impl::restore_state(estimation::StateReader& in) {
  in.expect("alarm_engine_state", 3);
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
  detail::restore(in, continuity);
}

void AlarmEngine::save(estimation::StateWriter& out) const {
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

AlarmEngine restore_engine(estimation::StateReader& in, const AlarmParams* expected) {
  in.expect("alarm_engine", 1);
  auto group = in.get<std::string>();
  auto names = in.get<std::vector<std::string>>();
  auto factor_names = in.get<std::vector<std::string>>();
  AlarmParams saved;
  alarms::restore(in, saved);
  if (expected != nullptr) {
    const std::string diff = param_differences(saved, *expected);
    if (!diff.empty()) {
      throw estimation::StateError("checkpoint of asset group '" + group +
                               "' was written with other alarm parameters (checkpoint -> configured: " + diff +
                               "); its baseline and detectors do not apply to this configuration");
    }
  }
  try {
    return AlarmEngine(std::move(group), std::move(names), std::move(factor_names), saved);
  } catch (const std::invalid_argument& e) {
    throw estimation::StateError(std::string("checkpoint: invalid engine configuration: ") + e.what());
  }
}

}  // namespace

AlarmEngine AlarmEngine::restore(estimation::StateReader& in, const AlarmParams& params) {
  AlarmEngine e = restore_engine(in, &params);
  e.impl_->restore_state(in);
  in.expect("alarm_engine_end", 1);
  return e;
}

AlarmEngine AlarmEngine::restore(estimation::StateReader& in) {
  AlarmEngine e = restore_engine(in, nullptr);
  e.impl_->restore_state(in);
  in.expect("alarm_engine_end", 1);
  return e;
}

}  // namespace causal::alarms
