// Internal state of AlarmEngine (not installed; shared by the engine's translation units).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/alarms/detectors.hpp"
#include "causal/alarms/factor_names.hpp"
#include "causal/alarms/statistics.hpp"

namespace causal::alarms::detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

enum KindIndex { kFeature = 0, kInnovation = 1, kNis = 2, kFactor = 3, kKindCount = 4 };
const char* kind_name(int kind_index);

// One scalar signal standardised against its baseline: z = (v - median) / (1.4826 MAD).
struct SignalMonitor {
  std::vector<double> baseline;  // raw (transformed) values collected during the baseline period
  RobustStats stats;
  bool monitored = false;
  double last_value = kNaN;
  double last_z = kNaN;          // (v - median) / scale: the plain estimate, used for levels and texts
  double detect_z = kNaN;        // conservative z fed to the detectors (see AlarmParams::baseline_confidence)
  double nis_z = kNaN;           // (v - median) / inflated scale, two-sided, for the NIS window
  double scale_inflation = 1.0;  // upper confidence bound of the scale / the estimate
  double location_margin = 0.0;  // confidence margin of the median, in sigmas
  ClippedCusum cusum;
  WindowMean level;              // recent z values: their median is the signal's current level
  double standardize(double v) const { return (v - stats.location) / stats.scale; }
};

struct FactorMonitor {
  FactorRef ref;
  std::vector<double> baseline;
  RobustStats stats;
  bool monitored = false;
  double last_value = kNaN;
  double last_std = kNaN;
  double last_z = kNaN;          // (x - median) / sqrt(scale^2 + std^2)
};

struct AlarmSlot {
  PersistenceLatch latch;
  int counter = 0;               // number of alarms raised so far for this (channel, kind)
  std::string id;
  Severity severity = Severity::Advisory;
  std::int64_t raised_time_ns = 0;
  std::uint64_t onset_index = 0;
  std::int64_t onset_time_ns = 0;
  double score = 0.0, threshold = 0.0;
  AlarmEvent last_event;
};

struct ChannelState {
  SignalMonitor feature;
  SignalMonitor innovation;
  WindowMean nis;                // clipped squared standardised innovations
  std::array<AlarmSlot, kKindCount> slots;
  std::vector<int> factors;      // indices of the factors of this channel's equation (outcome)
  double factor_stat = kNaN;     // max |z| over them
  int factor_argmax = -1;
  std::uint64_t factor_run_start_index = 0;  // first observation of the current run above threshold
  std::int64_t factor_run_start_time_ns = 0;
  bool factor_in_run = false;
  std::uint64_t rejected = 0;
  // Own-change evidence of the current feature excursion: sum and count of the (clipped) standardised
  // innovations since the feature CUSUM's onset. sum / sqrt(count) is the z statistic of their mean:
  // ~0 for a channel whose rise the causal links explain (a follower), large for a root.
  double own_sum = 0.0;
  int own_count = 0;
  double own_evidence() const { return own_count > 0 ? own_sum / std::sqrt(static_cast<double>(own_count)) : 0.0; }
  int baseline_from_filter = 0;  // baseline innovation values that were e / sqrt(S) (not log mean NIS)
  int baseline_from_nis = 0;
};

struct Onset {
  bool set = false;
  std::uint64_t index = 0;
  std::int64_t time_ns = 0;
  double level = 0.0;            // signal level (sigma) when recorded, for tie-breaks and the text
  double evidence = 0.0;         // own-change evidence when recorded (departures only), for tie-breaks
  void take_earlier(std::uint64_t i, std::int64_t t, double lv, double ev = 0.0) {
    if (!set || i < index) {
      set = true;
      index = i;
      time_ns = t;
      level = lv;
      evidence = ev;
    }
  }
};

// Onsets recorded while at least one alarm of the group is active (reset when all have cleared).
struct Episode {
  std::vector<Onset> own;        // innovation_rise onsets: the channel's own behaviour changed
  std::vector<Onset> departure;  // feature_drift onsets: the channel's condition level departed
  void reset(int channels) {
    own.assign(static_cast<std::size_t>(channels), Onset{});
    departure.assign(static_cast<std::size_t>(channels), Onset{});
  }
};

// Checkpoints of the engine's pieces (engine_checkpoint.cpp). restore() throws causal::StateError on a
// truncated, foreign or inconsistent section.
void save(causal::StateWriter& out, const SignalMonitor& s);
void restore(causal::StateReader& in, SignalMonitor& s);
void save(causal::StateWriter& out, const FactorMonitor& f);
void restore(causal::StateReader& in, FactorMonitor& f);
void save(causal::StateWriter& out, const AlarmSlot& slot);
void restore(causal::StateReader& in, AlarmSlot& slot);
void save(causal::StateWriter& out, const ChannelState& cs);
void restore(causal::StateReader& in, ChannelState& cs, int factor_count);
void save(causal::StateWriter& out, const Episode& e);
void restore(causal::StateReader& in, Episode& e, int channels);

}  // namespace causal::alarms::detail

namespace causal::alarms {

struct AlarmEngine::Impl {
  std::string group;
  std::vector<std::string> names;
  std::vector<std::string> factor_names;
  AlarmParams p;
  double h = 0.0;                // CUSUM decision interval
  double nis_thr = 0.0;
  std::vector<detail::ChannelState> ch;
  std::vector<detail::FactorMonitor> fac;
  std::uint64_t seen = 0;
  std::uint64_t rejected = 0;
  std::uint64_t not_running = 0;
  bool ready = false;
  detail::Episode episode;

  int channels() const { return static_cast<int>(names.size()); }
  // Root cause for an event of channel c whose own alarm began at `event_onset`.
  int root_cause(int c, std::uint64_t event_onset) const;
  Severity severity_for(int c, int kind) const;
  std::vector<int> explain_factors(int c, int root) const;
  std::string reason(int c, int kind, AlarmState state, int root, const Observation& obs) const;
  // Everything that changes after construction (engine_checkpoint.cpp); the configuration (group, names,
  // params) is written by AlarmEngine::save before it, and restore_state() runs on an engine constructed
  // from that configuration, so the derived structure (latch counts, factor references) is rebuilt.
  void save_state(causal::StateWriter& out) const;
  void restore_state(causal::StateReader& in);
};

}  // namespace causal::alarms
