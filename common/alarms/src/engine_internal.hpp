// Internal state of AlarmEngine (not installed; shared by the engine's translation units).
#pragma once

#include <algorithm>
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
#include "input_continuity.hpp"

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
  // Where the slow tracking started from (AlarmParams::baseline_tracking_observations): the location as
  // learned or as last re-baselined; tracking stays within half the size floor of it.
  double anchor_location = kNaN;
  // Observations left in which a location re-learned on the short confirmation window (12 correlated
  // values after a gap or step) is still refined, as a running mean (AlarmParams::baseline_tracking_observations).
  int refine_left = 0;
  // Reference of the escalation levels and of the limits on what the baseline may follow: the learned
  // baseline location, moved only by a gap / restart re-baseline or a machine-wide operating change (not
  // by slow tracking or a single channel's step; see AlarmParams::max_absorbed_ratio).
  double reference_location = kNaN;
  // The channel's healthy range (feature signals): log values of the warm-up (collected while warming up)
  // and the top of the range the median of level_window reached over the warm-up and the baseline, as a log
  // ratio over the baseline location. A level inside it is not a degradation (AlarmParams::advisory_ratio);
  // it moves with the location (tracking, re-baselines).
  std::vector<double> warmup;
  double healthy_top = kNaN;
  int range_left = 0;            // observations in which the range still learns (healthy_range_observations)
  // The range the channel's level came back from while healthy (its wander over days), as log ratios over the
  // location (like healthy_top): wander_top = the highest excursion it returned from, excursion_peak = the highest
  // level of the excursion under way (update_step_run). A degradation does not return, so it is never learned.
  double wander_top = kNaN;
  double excursion_peak = kNaN;
  int excursion_above = 0;       // its observations at or above the size floor (advisory_ratio)
  double excursion_last = kNaN;  // the level's log ratio at the previous observation
  int excursion_jumped = 0;      // 1: the level rose by the size floor in one observation (a step, not learned)
  double standardize(double v) const { return (v - stats.location) / stats.scale; }
  // Log ratio of the current level (median of the level window) over the current / the lower of the
  // current and reference locations (escalation). NaN without a level.
  double level_log_ratio() const { return level.median() * stats.scale; }
  double escalation_reference() const {
    return std::isfinite(reference_location) ? std::min(reference_location, stats.location) : stats.location;
  }
  double escalation_log_ratio() const { return level_log_ratio() + stats.location - escalation_reference(); }
};

// Feeds one transformed value to a signal after the baseline (engine_signals.cpp): plain and conservative z,
// the CUSUM, the level window, and the slow tracking of the location (feature signals,
// AlarmParams::baseline_tracking_observations) while nothing builds up. `track` = the channel may follow.
void update_signal(SignalMonitor& s, double v, const AlarmParams& p, const Observation& obs, bool track);
struct ChannelState;
// Counts the runs of observations at a step's size (ChannelState::excursion_obs) and at the size floor
// (ChannelState::size_run).
void update_step_run(ChannelState& cs, const AlarmParams& p);

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
  // Escalation on persistence (AlarmParams::escalation_persistence): consecutive observations whose level
  // reached the Warning / Critical level while the alarm is active.
  int warning_run = 0, critical_run = 0;
  // Root cause of this alarm, re-evaluated every observation (AlarmParams::root_cause_margin_z): the
  // current verdict, a challenger and for how many consecutive observations it has out-evidenced it.
  int root = -1;
  double root_confidence = 0.0;
  int challenger = -1;
  int challenger_run = 0;
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
  // Current run of consecutive observations whose level is at least operating_step_ratio x the baseline,
  // and the sum of their plain z, for the abrupt-step test (AlarmParams::operating_step_ratio). A run, not
  // the CUSUM's excursion: a step that lands while the CUSUM is already up (a daily-cycle high, a slow
  // wander) is still recognised as a step.
  int excursion_obs = 0;
  double excursion_sum_z = 0.0;
  int change_counter = 0;        // operating-change / discontinuity events of this channel (id counter)
  // Consecutive observations whose level (median of level_window) reached the size floor
  // (AlarmParams::advisory_ratio): the floor must hold for level_window observations before a raise.
  int size_run = 0;
  // The level event (AlarmEngine::level_event): the last escalation_persistence log level ratios over the
  // reference (oldest first) and the highest of their minimum since the channel's alarms opened (NaN: none).
  std::vector<double> recent_ratio;
  double level_peak = kNaN;
  bool any_active() const {
    for (const auto& s : slots)
      if (s.latch.active()) return true;
    return false;
  }
};

// The asset group is under confirmation (AlarmParams::confirmation_observations): detectors held, values
// collected, decision at the end of the window.
struct Confirmation {
  bool active = false;
  bool gap = false;              // started by a discontinuity (else by an abrupt step of step_channel)
  bool restart = false;          // the discontinuity is a restart after not-running observations
  int step_channel = -1;
  double gap_s = 0.0;            // length of the gap that started it (0: flagged by the source)
  std::uint64_t start_index = 0;
  std::int64_t start_time_ns = 0;
  std::uint64_t step_onset_index = 0;
  std::int64_t step_onset_time_ns = 0;
  std::vector<std::vector<double>> feature, innovation;  // per channel, the window's transformed values
  void reset() { *this = Confirmation{}; }
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

// Checkpoints of the engine's pieces (engine_checkpoint.cpp). restore() throws estimation::StateError on a
// truncated, foreign or inconsistent section.
void save(estimation::StateWriter& out, const SignalMonitor& s);
void restore(estimation::StateReader& in, SignalMonitor& s);
void save(estimation::StateWriter& out, const FactorMonitor& f);
void restore(estimation::StateReader& in, FactorMonitor& f);
void save(estimation::StateWriter& out, const AlarmSlot& slot);
void restore(estimation::StateReader& in, AlarmSlot& slot);
// A channel, the episode and the confirmation window are saved as part of the engine's state (their restore
// needs the engine's counts of channels and factors).

// ---- the detector table (detector_table.cpp) ------------------------------------------------------
// Alarm kinds are data: one row per kind with what it watches and how its statistic, threshold, onset and
// severity are read from the engine's state. The engine loops over the table; a new kind is one row plus
// one file in src/detectors/ that returns its DetectorKind (and its KindIndex, which sizes the per-channel
// alarm slots).
struct DetectorReading {
  bool enabled = false;          // configured on and its signal monitored
  double statistic = kNaN;       // NaN: no value this observation (the latch neither advances nor resets)
  double threshold = 0.0;
};
struct DetectorKind {
  const char* name;              // AlarmEvent::kind
  const char* signal;            // what it watches (documentation, diagnostics)
  const char* statistic;         // how (documentation)
  const char* category;          // AlarmEvent::category of its alarms
  // Statistic and threshold of channel c now (may update the detector's own run state).
  DetectorReading (*read)(AlarmEngine::Impl& m, int c, const Observation& obs);
  // Estimated start of the change when an alarm is raised: (index, time); records the episode onset.
  void (*onset)(AlarmEngine::Impl& m, int c, const Observation& obs, std::uint64_t& index, std::int64_t& time_ns);
  // Severity the current level calls for (before persistence, AlarmParams::escalation_persistence).
  Severity (*level_severity)(const AlarmEngine::Impl& m, int c);
  // The kind's sentence of a raised / escalated alarm's reason: what moved, from what to what, the
  // statistic against its threshold and its false-alarm design, since when.
  std::string (*describe)(const AlarmEngine::Impl& m, int c, const AlarmSlot& slot, const Observation& obs);
};
const std::array<DetectorKind, kKindCount>& detector_table();
// The rows, one file each (src/detectors/<kind>.cpp).
DetectorKind feature_drift_detector();
DetectorKind innovation_rise_detector();
DetectorKind innovation_nis_detector();
DetectorKind factor_shift_detector();
// Severity of a level in baseline sigmas: warning_sigma and critical_sigma (advisory below, or not finite).
Severity severity_by_sigma(const AlarmParams& p, double level);

// Number formatting of the reasons (alarm_explain.cpp).
std::string at(std::uint64_t index, std::int64_t time_ns);  // "observation N (YYYY-MM-DD hh:mm:ss UTC)"
std::string signed_fixed(double v, int decimals);
std::string fixed(double v, int decimals);
std::string general(double v);  // 4 significant digits

}  // namespace causal::alarms::detail

namespace causal::alarms {

struct AlarmEngine::Impl {
  std::string group;
  std::string id_scope;  // "" or e.g. "sample": ids "<group>/<scope>/<channel>/<kind>/<n>" (set_id_scope)
  // The id of the n-th alarm (or event) of one kind on channel c (0-based), unique per engine and scope.
  std::string alarm_id(int c, const std::string& kind, std::uint64_t n) const {
    return group + (id_scope.empty() ? "" : "/" + id_scope) + "/" + std::to_string(c + 1) + "/" + kind + "/" +
           std::to_string(n);
  }
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
  // Time awareness: the baseline's observation times give the usual interval; a gap beyond
  // gap_multiple x it is a discontinuity.
  std::vector<std::int64_t> baseline_times;
  double median_interval_ns = 0.0;
  bool has_last_time = false;
  std::int64_t last_time_ns = 0;
  detail::Confirmation confirm;
  bool stopped = false;          // the last observation was skipped by the operating-state gate
  std::uint64_t discontinuities = 0;
  std::uint64_t operating_changes = 0;
  detail::IndexContinuity continuity;  // input lost before the engine (input_continuity.hpp)

  int channels() const { return static_cast<int>(names.size()); }
  // Root cause for an event of channel c whose own alarm began at `event_onset`.
  int root_cause(int c, std::uint64_t event_onset) const;
  Severity severity_for(int c, int kind) const;
  std::vector<int> explain_factors(int c, int root) const;
  std::string reason(int c, int kind, AlarmState state, int root, const Observation& obs) const;
  // Own-change evidence of every channel that departed (feature CUSUM in excursion or an alarm active);
  // NaN for the others. Confidence that `root` is the root cause (see AlarmParams::root_cause_margin_z).
  std::vector<double> departed_evidence() const;
  double attribution_confidence(int root, const std::vector<double>& evidence) const;
  // The runner-up of attribution_confidence: the rival with the largest evidence (-1: none).
  int attribution_rival(int root, const std::vector<double>& evidence) const;
  // Re-evaluates the root cause of channel c's active alarm in `slot`; returns a reason text when the
  // verdict changed (empty otherwise).
  std::string reevaluate_root(int c, detail::AlarmSlot& slot, const std::vector<double>& evidence);
  // Gaps and operating changes (operating_changes.cpp).
  // `lost`: observations the source skipped right before this one (input lost, not a pause): their time is
  // no gap, and a discontinuity flag on the first observation after them is the loss's.
  bool is_discontinuity(const Observation& obs, std::uint64_t lost) const;
  // Appends the HEALTH event input_lost (raised and cleared at once) naming the range (input_continuity.cpp).
  void report_lost(const detail::LostRange& r, const Observation& obs, std::vector<AlarmEvent>& events);
  void start_confirmation(const Observation& obs, bool gap, int step_channel, double gap_s);
  // The channel whose feature CUSUM just crossed in an abrupt, large step (AlarmParams::operating_step_ratio),
  // -1 when none.
  int abrupt_step() const;
  // Starts an alarm of (c, kind): id, onset, episode onsets, severity. Returns nothing: events are built
  // after every detector of the observation has been read (simultaneous onsets).
  void begin_alarm(int c, int kind, const Observation& obs);
  // Counts the level's persistence (AlarmParams::escalation_persistence); true when the severity rose.
  bool escalate(int c, int kind);
  // The channel has a ratio scale (log feature with a reference): its severities follow its level event.
  bool ratio_scale(int c) const;
  // An alarm of channel c is open and its confirmed level reached ratio x its reference (AlarmEngine::level_reached).
  bool level_reached(int c, double ratio) const;
  // At the end of a step's confirmation window: the channels that settled at a step's size (none for a gap).
  std::vector<bool> settled_steps() const;
  // Raises channel c's feature_drift alarm for a step that was not confirmed as an operating change (still
  // rising, or a single channel beyond max_absorbed_ratio); `why` prefixes the reason.
  void raise_unconfirmed_step(int c, const Observation& obs, const std::string& why, std::vector<AlarmEvent>& events);
  // Appends an operating-change event of channel c (raised and cleared at once: a point event).
  void emit_change(int c, const char* kind_name, const std::string& why, const Observation& obs,
                   std::vector<AlarmEvent>& events);
  // Adds the observation's values to the window; at its end decides and appends the events.
  void confirm_step(const Observation& obs, const std::vector<double>& feat, const std::vector<double>& innov,
                    std::vector<AlarmEvent>& events);
  AlarmEvent make_event(int c, int kind, AlarmState state, const Observation& obs);
  // Everything that changes after construction (engine_checkpoint.cpp); the configuration (group, names,
  // params) is written by AlarmEngine::save before it, and restore_state() runs on an engine constructed
  // from that configuration, so the derived structure (latch counts, factor references) is rebuilt.
  void save_state(estimation::StateWriter& out) const;
  void restore_state(estimation::StateReader& in);
};

}  // namespace causal::alarms

namespace causal::alarms::detail {
// The size floor (AlarmParams::advisory_ratio): true when channel c's condition level has been at least
// advisory_ratio x its baseline for level_window observations, or when it has no ratio scale (then the
// statistics decide alone).
bool size_matters(const AlarmEngine::Impl& m, int c);
// Feeds the channel's current level ratio to its level event (ChannelState::recent_ratio, level_peak).
void update_level_event(AlarmEngine::Impl& m, int c);
// The top of the healthy range from the warm-up and baseline log values (SignalMonitor::healthy_top).
double healthy_range_top(const std::vector<double>& warmup, const std::vector<double>& baseline, int window);
}  // namespace causal::alarms::detail
