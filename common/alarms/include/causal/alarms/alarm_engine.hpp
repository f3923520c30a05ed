// AlarmEngine: turns the causal twin's per-observation outputs (condition features, one-step innovations
// of the causal filter, causal factors) for one asset group into alarms that explain themselves.
//
// Pipeline per observation (see docs in alarm_params.hpp for every threshold):
//  1. warm-up (ignored), then baseline: the first baseline_observations healthy observations give each
//     signal a robust location/scale (median, 1.4826 MAD): log feature, standardised innovation
//     e_k/sqrt(S_k) (or log mean NIS), every causal factor.
//  2. monitoring, per channel k:
//       feature_drift   : clipped one-sided CUSUM on the standardised log feature (level rose)
//       innovation_rise : same CUSUM on the standardised innovation: the part of channel k the other
//                         channels do not explain rose -> k's OWN behaviour changed
//       innovation_nis  : window mean of clipped squared standardised innovations (upward departures
//                         only, by default): the model no longer explains the channel
//       factor_shift    : max |z| of outcome k's factors vs their baseline, Bonferroni threshold
//     each with persistence / hysteresis (PersistenceLatch), severities, one alarm per (channel, kind)
//     while active; escalations and the clearing republish the same alarm id.
//     Kinds are rows of a table (detector_table.cpp): statistic, threshold, onset, severity, reason text.
//     Severities escalate only on persistence (AlarmParams::escalation_persistence).
//  2b. gaps and operating changes (AlarmParams, "gaps and operating changes"): a discontinuity (flag, time
//     gap, restart after a stop) or an abrupt large step holds the detectors for a confirmation window;
//     then levels that settled are re-baselined and reported as events of category "operating_change"
//     (raised and cleared at once), a step that keeps rising raises its feature_drift alarm. Indices a
//     consecutively numbered source skipped are input the twin lost, not a gap: one "health" event
//     "input_lost" naming the range (raised and cleared at once), the detectors go on.
//  3. root cause (per episode = period during which at least one alarm is active): the channel whose
//     own behaviour changed first -- an innovation_rise onset, else a feature departure, among channels
//     whose change began no later than the alarmed channel's; simultaneous onsets (within
//     onset_tolerance) are resolved by the own-change evidence (z statistic of the innovations since the
//     departure began), then by size. Followers (channels that rise only because the causal links carry
//     the root's change) show a departure without own-change evidence and get the root's id. A channel
//     whose trouble began with its own change clearly AFTER the first root is an independent root
//     (a second fault) and is its own root cause. The verdict is re-evaluated at every observation
//     (AlarmParams::root_cause_margin_z); each event carries the attribution's confidence.
//
// Sample-level use: feed one Observation per factor publication (mean_nis filled from the CausalFactorBatch
// nis_mean, features optional e.g. a block RMS) with AlarmParams::sample_level(n_healthy_publications).
// The innovation signal is then log mean NIS: a channel whose waveform is no longer predicted from the
// others (bearing damage adds impulsive, unexplained energy) raises innovation_rise / innovation_nis.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "causal/alarms/alarm_event.hpp"
#include "causal/alarms/alarm_params.hpp"
#include "causal/alarms/observation.hpp"

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::alarms {

// State of one monitored scalar signal (diagnostics).
struct SignalDiagnostics {
  bool monitored = false;        // baseline learned with enough finite values
  double baseline_location = 0;  // median over the baseline (log units for log features)
  double baseline_scale = 0;     // 1.4826 MAD
  double baseline_lag1_autocorr = 0;
  double last_z = 0;             // latest standardised value (NaN if none)
  double cusum = 0;              // current CUSUM statistic (feature / innovation)
};

struct ChannelDiagnostics {
  SignalDiagnostics feature;
  SignalDiagnostics innovation;
  double nis_window_mean = 0;    // window mean of clipped squared standardised innovations
  double factor_max_abs_z = 0;   // max |z| over the channel's (outcome's) monitored factors
  int monitored_factors = 0;
  std::uint64_t rejected_values = 0;  // non-finite / non-positive (log) inputs skipped for this channel
  int root_cause = -1;           // current root-cause verdict for this channel (-1 when no episode)
};

// The level event of one channel (log-transformed features): warning, critical and end of life are multiples of
// the channel's healthy reference level, judged by ONE statistic, the median of the last level_window values
// held for escalation_persistence observations. The alarm's severity and the forecast's "reached" both read
// level_reached(), so they cannot disagree.
struct LevelEvent {
  bool ratio_scale = false;      // log-transformed, monitored feature: the levels are defined
  double reference_log = 0;      // log of the healthy reference level (NaN without one)
  double level_ratio = 0;        // current level / reference (median of the last level_window); NaN if none
  double peak_ratio = 0;         // highest confirmed level / reference since the channel's alarms opened; NaN if none
};

class AlarmEngine {
 public:
  // channel_names: G >= 1 names (G fixed for the engine's life). factor_names: F names (may be empty)
  // following the project convention; factors whose name cannot be parsed are used in explanations
  // only. Throws std::invalid_argument on empty channel list or invalid params.
  AlarmEngine(std::string asset_group, std::vector<std::string> channel_names, std::vector<std::string> factor_names,
              AlarmParams params);
  ~AlarmEngine();
  AlarmEngine(AlarmEngine&&) noexcept;
  AlarmEngine& operator=(AlarmEngine&&) noexcept;
  AlarmEngine(const AlarmEngine&) = delete;
  AlarmEngine& operator=(const AlarmEngine&) = delete;

  // Processes one observation; returns the events it triggered (raised / escalated / cleared), in
  // channel order. Observations whose vectors have the wrong size are rejected (counted, no event).
  std::vector<AlarmEvent> observe(const Observation& obs);

  // Ids are "<asset_group>/<channel 1-based>/<kind>/<n>"; with a scope "<asset_group>/<scope>/<channel>/...".
  // Engines of one asset group on different time scales must differ here (the alarm topic keeps the last value
  // per id: a condition-level CLEARED would otherwise overwrite a sample-level alarm still open). Not saved in
  // checkpoints: the owner sets it again after restore(). Call before the first observation.
  void set_id_scope(std::string scope);
  bool baseline_ready() const;
  int channel_count() const;
  const std::string& asset_group() const;
  const std::vector<std::string>& channel_names() const;
  const std::vector<std::string>& factor_names() const;
  const AlarmParams& params() const;
  double cusum_threshold() const;     // h
  double nis_threshold() const;
  std::uint64_t observations_seen() const;
  std::uint64_t rejected_observations() const;
  // Observations skipped by the operating-state gate (every channel far below its baseline: not running).
  std::uint64_t not_running_observations() const;
  // Discontinuities seen (flagged, time gaps, restarts after a stop) and operating-change events raised.
  std::uint64_t discontinuities() const;
  std::uint64_t operating_changes() const;
  // Observations a consecutively numbered source skipped (lost before the engine, not a recording gap: one
  // HEALTH event "input_lost" per missing range, src/input_continuity.hpp), and the number of such ranges.
  std::uint64_t lost_observations() const;
  std::uint64_t input_losses() const;
  ChannelDiagnostics channel_diagnostics(int channel) const;
  // The channel's level event (see LevelEvent); level_reached(c, r): an alarm of channel c is open and its
  // confirmed level reached r x the reference (the warning / critical / end-of-life crossing). Throw
  // std::invalid_argument for a channel out of range.
  LevelEvent level_event(int channel) const;
  bool level_reached(int channel, double ratio) const;
  // Latest event of every active alarm (state Raised or Escalated), channel order.
  std::vector<AlarmEvent> active_alarms() const;

  // ---- checkpoints (crash and restart safety) -------------------------------------------------------
  // Writes the engine's whole state: asset group, channel and factor names, parameters, baselines (or the
  // values collected so far), every detector, latch, episode onset and counter, the alarm id counters
  // and the latest event of every alarm. An engine restored from it and fed the rest of a stream emits
  // exactly the events, ids, active alarms and diagnostics of the engine that never stopped.
  void save(estimation::StateWriter& out) const;
  // Restores an engine written by save(), refusing one written with other parameters: a baseline and
  // detectors designed under other thresholds cannot continue as if nothing had changed. Throws
  // estimation::StateError (truncated or foreign checkpoint; the message names every differing parameter).
  static AlarmEngine restore(estimation::StateReader& in, const AlarmParams& params);
  // Same, with the parameters stored in the checkpoint (offline inspection, tools).
  static AlarmEngine restore(estimation::StateReader& in);

  // Opaque state (engine_internal.hpp); public only so the library's detector table can name it.
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace causal::alarms
