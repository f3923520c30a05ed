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
  io(o.set, o.index, o.time_ns, o.level, o.evidence);
}

template <class Io, class S>
void signal_fields(Io io, S& s) {
  io.tag("signal_monitor", 4);
  io(s.baseline);
  io.section(s.stats);
  io(s.monitored, s.last_value, s.last_z, s.detect_z, s.nis_z, s.scale_inflation, s.location_margin);
  io.object(s.cusum);
  io.object(s.level);
  io(s.anchor_location, s.refine_left, s.reference_location, s.warmup, s.healthy_top, s.range_left, s.wander_top,
     s.excursion_peak, s.excursion_above, s.excursion_last, s.excursion_jumped);
}

template <class Io, class F>
void factor_fields(Io io, F& f) {
  io.tag("factor_monitor", 1);
  io(f.baseline);
  io.section(f.stats);
  io(f.monitored, f.last_value, f.last_std, f.last_z);
}

// The severity is written as an int32 and checked on restore.
template <class Io, class A>
void slot_fields(Io io, A& slot) {
  io.tag("alarm_slot", 2);
  io.object(slot.latch);
  io(slot.counter, slot.id);  // alarm id counter: ids are never reused across a restart
  io.template as<std::int32_t>(slot.severity);
  if constexpr (Io::restoring) {
    const auto severity = static_cast<int>(slot.severity);
    if (slot.counter < 0 || severity < static_cast<int>(Severity::Advisory) ||
        severity > static_cast<int>(Severity::Critical)) {
      throw estimation::StateError("checkpoint: alarm_slot '" + slot.id + "' holds an invalid counter or severity");
    }
  }
  io(slot.raised_time_ns, slot.onset_index, slot.onset_time_ns, slot.score, slot.threshold);
  io.section(slot.last_event);
  io(slot.warning_run, slot.critical_run, slot.root, slot.root_confidence, slot.challenger, slot.challenger_run);
}

// factor_count: the engine's factors, which factor_argmax refers to (checked on restore).
template <class Io, class C>
void channel_fields(Io io, C& cs, int factor_count) {
  io.tag("alarm_channel", 4);
  io.section(cs.feature);
  io.section(cs.innovation);
  io.object(cs.nis);
  io.same_count(cs.slots.size(), "alarm kinds");
  for (auto& slot : cs.slots) io.section(slot);
  io(cs.factor_stat, cs.factor_argmax);
  if constexpr (Io::restoring) {
    if (cs.factor_argmax < -1 || cs.factor_argmax >= factor_count) {
      throw estimation::StateError("checkpoint: alarm_channel refers to factor " + std::to_string(cs.factor_argmax) +
                                   " of " + std::to_string(factor_count));
    }
  }
  io(cs.factor_run_start_index, cs.factor_run_start_time_ns, cs.factor_in_run, cs.rejected, cs.own_sum,
     cs.own_count, cs.baseline_from_filter, cs.baseline_from_nis, cs.excursion_obs, cs.excursion_sum_z,
     cs.change_counter, cs.size_run, cs.recent_ratio, cs.level_peak);
}

// A restore starts from an episode of `channels` empty onsets; the counts must match them.
template <class Io, class E>
void episode_fields(Io io, E& e, int channels) {
  io.tag("alarm_episode", 1);
  if constexpr (Io::restoring) e.reset(channels);
  io.same_count(e.own.size(), "episode onsets (own)");
  for (auto& o : e.own) onset_fields(io, o);
  io.same_count(e.departure.size(), "episode onsets (departure)");
  for (auto& o : e.departure) onset_fields(io, o);
}

// The window's values per channel: none (no window open) or one pair of vectors per channel.
template <class Io, class C>
void confirmation_fields(Io io, C& c, int channels) {
  io.tag("alarm_confirmation", 1);
  io(c.active, c.gap, c.restart, c.step_channel, c.gap_s, c.start_index, c.start_time_ns, c.step_onset_index,
     c.step_onset_time_ns);
  auto n = static_cast<std::uint64_t>(c.feature.size());
  io(n);
  if constexpr (Io::restoring) {
    if ((n != 0 && n != static_cast<std::uint64_t>(channels)) || c.step_channel < -1 || c.step_channel >= channels) {
      throw estimation::StateError("checkpoint: alarm_confirmation does not fit " + std::to_string(channels) +
                                   " channels");
    }
    c.feature.resize(static_cast<std::size_t>(n));
    c.innovation.resize(static_cast<std::size_t>(n));
  }
  for (std::size_t i = 0; i < n; ++i) io(c.feature[i], c.innovation[i]);
}

}  // namespace

void save(estimation::StateWriter& out, const SignalMonitor& s) { signal_fields(estimation::SaveFields{out}, s); }
void restore(estimation::StateReader& in, SignalMonitor& s) { signal_fields(estimation::RestoreFields{in}, s); }
void save(estimation::StateWriter& out, const FactorMonitor& f) { factor_fields(estimation::SaveFields{out}, f); }
void restore(estimation::StateReader& in, FactorMonitor& f) { factor_fields(estimation::RestoreFields{in}, f); }
void save(estimation::StateWriter& out, const AlarmSlot& slot) { slot_fields(estimation::SaveFields{out}, slot); }
void restore(estimation::StateReader& in, AlarmSlot& slot) { slot_fields(estimation::RestoreFields{in}, slot); }

}  // namespace detail

namespace {

// Everything that changes after construction: M is AlarmEngine::Impl, const when saving. A restore runs on an
// engine built from the saved configuration, so the counts of channels, factors and kinds must match it.
template <class Io, class M>
void engine_state_fields(Io io, M& m) {
  io.tag("alarm_engine_state", 3);
  io(m.seen, m.rejected, m.not_running, m.ready);
  io.same_count(m.ch.size(), "channel");
  for (auto& cs : m.ch) detail::channel_fields(io, cs, static_cast<int>(m.fac.size()));
  io.same_count(m.fac.size(), "factor");
  for (auto& f : m.fac) io.section(f);
  detail::episode_fields(io, m.episode, m.channels());
  io(m.baseline_times, m.median_interval_ns, m.has_last_time, m.last_time_ns);
  if constexpr (Io::restoring) {
    detail::Confirmation c;  // restored aside: a window that does not fit leaves the engine's as it was
    detail::confirmation_fields(io, c, m.channels());
    m.confirm = std::move(c);
  } else {
    detail::confirmation_fields(io, m.confirm, m.channels());
  }
  io(m.discontinuities, m.operating_changes, m.stopped);
  io.section(m.continuity);
}

// The configuration the engine is rebuilt from (asset group, names, parameters).
template <class Io, class S, class V, class P>
void engine_config_fields(Io io, S& group, V& names, V& factor_names, P& params) {
  io.tag("alarm_engine", 1);
  io(group, names, factor_names);
  io.section(params);
}

}  // namespace

void AlarmEngine::Impl::save_state(estimation::StateWriter& out) const {
  engine_state_fields(estimation::SaveFields{out}, *this);
}

void AlarmEngine::Impl::restore_state(estimation::StateReader& in) {
  engine_state_fields(estimation::RestoreFields{in}, *this);
}

void AlarmEngine::save(estimation::StateWriter& out) const {
  const Impl& m = *impl_;
  engine_config_fields(estimation::SaveFields{out}, m.group, m.names, m.factor_names, m.p);
  m.save_state(out);
  out.begin("alarm_engine_end", 1);  // catches a reader that consumed a different number of fields
}

namespace {

AlarmEngine restore_engine(estimation::StateReader& in, const AlarmParams* expected) {
  std::string group;
  std::vector<std::string> names, factor_names;
  AlarmParams saved;
  engine_config_fields(estimation::RestoreFields{in}, group, names, factor_names, saved);
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
