// Every threshold of the alarm engine, with the statistical reasoning behind its default.
// Nothing here is fitted to a particular recording: the detectors standardise every signal by the
// asset group's own healthy baseline (median / MAD), so the defaults are in baseline-sigma units,
// in false-alarm probabilities / average run lengths, or in physical level ratios.
#pragma once

#include <string>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::alarms {

// Every field below is also listed, by name, in alarm_params.cpp (for_each_param): checkpoints carry the
// parameters they were written with, and a restore under other parameters is refused.

struct AlarmParams {
  // ---------------------------------------------------------------- baseline ------------------------
  // Observations skipped at the start: the causal filter starts from a diffuse prior (p0) and its
  // innovations / factors are a transient until the factors have converged (a few times the number of
  // regressors per outcome, 2G-2 = 6 for G = 4, M = 1). 20 covers ~3 such time constants.
  int warmup_observations = 20;
  // Healthy observations that define the baseline (after the warm-up). With n = 120 the median is
  // known to ~1.25/sqrt(n) = 0.11 sigma and the MAD scale to ~1.17/sqrt(n) = 11 %: the thresholds
  // below are then within ~0.1 sigma of their design value, small against the reference value k.
  int baseline_observations = 120;
  // A signal (one channel's feature, innovation or one factor) is monitored only if at least this
  // fraction of its baseline values were finite; otherwise it stays unmonitored (reported in diagnostics).
  double min_baseline_coverage = 0.5;
  // The baseline median and MAD are estimates (from n values): with n = 120 the scale is off by ~11 %
  // (1 sd) and an underestimated scale shortens the in-control ARL by an order of magnitude (measured:
  // 1.4e-5 false raises per channel-observation instead of the nominal 1e-6). The engine therefore
  // standardises with the upper one-sided `baseline_confidence` bound of the scale and a location margin
  // (sd(MAD)/MAD = 1.166/sqrt(n), sd(median) = 1.2533 sigma/sqrt(n) for Gaussian data): the design ARL
  // then holds for at least this fraction of baselines ("guaranteed conditional performance").
  double baseline_confidence = 0.9;

  // ---------------------------------------------------------------- CUSUM design --------------------
  // Shared by the feature-drift and innovation-rise detectors (one-sided upper CUSUM on z, the signal
  // standardised by the baseline median / 1.4826 MAD; see ClippedCusum).
  // k = half the shift the chart is fastest for: 1.5 -> tuned to 3-sigma shifts. Smaller shifts still
  // accumulate if they exceed k; the chart deliberately ignores level wander below ~1.5 sigma
  // (temperature, load), which a long run-to-failure test inevitably has.
  double cusum_k = 1.5;
  // In-control average run length per detector, in observations (Siegmund's approximation gives h;
  // h = 3.94 for k = 1.5). Why so large: a group of G = 4 channels runs ~3 CUSUM-type detectors per
  // channel; 1e6 nominal i.i.d. ARL0 keeps the group's nominal false-alarm rate at ~1 per 8e4
  // observations (1.6 years at one snapshot per 10 min). Real baselines are mildly autocorrelated
  // (lag-1 0.0-0.3 measured on the healthy IMS bearings), which shortens the ARL of an i.i.d. design;
  // simulated with the baseline margins below: AR(1) lag-1 0.25 -> ARL0 1.9e6, lag-1 0.5 -> 5e4.
  double target_arl0 = 1e6;
  // Winsorising of z before it enters a CUSUM: one observation adds at most clip - k = 2.5 < h, so a
  // single spike can never raise an alarm (validate() enforces h > clip - k when raise_persistence is 1).
  double clip_sigma = 4.0;
  // Cap of the CUSUM at cap_factor * h: keeps the time to clear after a long fault short (see ClippedCusum).
  double cusum_cap_factor = 2.0;
  // Hysteresis: an active alarm clears when its statistic is < clear_fraction * (raise threshold) for
  // clear_persistence consecutive observations. 12 = the NIS window: an alarm cannot clear while its
  // evidence window still holds anomalous observations, and a channel whose unexplained part comes in
  // bursts (a progressing fault) is not re-announced for every burst. With S capped at 2h and a healthy
  // signal draining >= k per observation, clearing takes ~ (2 - 0.5) h / k + 12 = 16 observations; a
  // still-shifted process (mean >= k) keeps S from draining and cannot clear.
  double clear_fraction = 0.5;
  int raise_persistence = 1;
  // The innovation detectors (innovation_rise, innovation_nis) raise only after this many consecutive
  // observations at or above their threshold. A burst of 2-4 snapshots (a short excursion, a knock) drives
  // the innovation CUSUM and the 12-snapshot NIS mean over their thresholds at once; alone it is held by the
  // size floor, but on the crest of a channel's slow wander (its level above the floor for hours) it raised a
  // second and third alarm on that channel. 4 = one more than such a burst's own span above the threshold
  // (docs/alarm-rules.md section 9). A change of the channel's own behaviour persists.
  int innovation_persistence = 4;
  int clear_persistence = 12;
  // Current level of a signal (for severities) = median of the last level_window standardised values:
  // robust to one outlier among 5.
  int level_window = 5;

  // ---------------------------------------------------------------- feature drift -------------------
  bool feature_enabled = true;
  // Scale features (RMS, mean |x|, peak, kurtosis) are positive and change multiplicatively: log makes
  // a given relative change equally significant at any level and makes their spread near-Gaussian.
  bool feature_log_transform = true;
  // Severity of a feature-drift alarm from the physical level ratio now / baseline median
  // (log-transformed features): Advisory = statistically significant rise; Warning = doubled (+6 dB),
  // Critical = four times (+12 dB): the customary 6 dB-per-step alert ladder of vibration trending.
  double warning_ratio = 2.0;
  double critical_ratio = 4.0;
  // Minimum effect (size floor) of EVERY degradation alarm, on top of its statistical test: no alarm is
  // raised while the channel's condition level (median of the last level_window values, so one snapshot
  // cannot carry it) is below advisory_ratio x its baseline. 1.08 = +8 % = +0.67 dB. Why a size at all: a
  // long healthy recording wanders by a few percent (temperature, load, re-mounting; +1.5 % to +7 % measured
  // on month-long IMS-format runs), which is "+3 sigma" against a baseline learned on a quiet early window.
  // Why this size (docs/alarm-rules.md): above that healthy wander, below the first significant rise of a
  // real failure (IMS test 2, bearing 1: +8.8 % at snapshot 537, four snapshots into its rise, +10.4 % at
  // 547). It is an early, "watch the trend" tier well below ISO 20816 practice for action (ALERT = baseline
  // + 25 % of the zone B/C boundary, i.e. ~x1.5-x2 the baseline of a machine running in zone A/B, which is
  // where warning_ratio sits). Log-transformed features only (a ratio needs a scale feature); 1 = no floor.
  // The channel's own healthy range counts too: the level must also stand above the highest median of
  // level_window the channel showed over its warm-up and baseline by half the floor (sqrt(advisory_ratio)),
  // so a baseline learned in a low stretch does not turn a return to the channel's earlier level into an
  // alarm; a channel that was flat (IMS test 2, bearing 1: top +2.8 %) keeps the floor at advisory_ratio.
  // The range is kept as a ratio over the baseline location, so it moves with it (tracking, re-baselines).
  double advisory_ratio = 1.08;
  // Slow healthy drift: while a channel's feature CUSUM is at 0 (nothing building up), no alarm is active
  // and no confirmation runs, its baseline location follows the feature with an exponential forgetting of
  // this many observations, each step limited to +-cusum_k sigma (1008 = one week at 10-minute spacing:
  // a +7 %-per-month drift is followed with a lag of ~1.6 %, a failure that rises within hours or days
  // moves it by nothing: it is frozen as soon as the CUSUM starts to build). The tracked location never
  // departs from the reference (learned baseline, or the level after a gap / machine-wide operating change)
  // by more than half the size floor: a fault slower than the tracking is still alarmed at
  // advisory_ratio^1.5 over its reference. 0 = no tracking.
  int baseline_tracking_observations = 1008;
  // The healthy range of the size floor (advisory_ratio) is learned over this many observations from the start
  // (warm-up and baseline included): after the baseline, while none of the channel's alarms is active, the
  // range's top follows the highest median of level_window, up to max_absorbed_ratio / sqrt(advisory_ratio)
  // over the location (so a fault during those days is still alarmed by x1.5). Like the baseline, those
  // observations must then be healthy, and a slow fault that starts in them is alarmed late.
  // 0 (shipped; any value <= warm-up + baseline): the range of the warm-up and baseline only. 432 (3 days at 10
  // minutes) halves the false alarms on a +-10 % wander over days but delays faults that begin in those 3
  // days (docs/alarm-rules.md, section 9).
  int healthy_range_observations = 0;
  // A single channel that steps and settles while the rest of the machine does not move is not a confirmed
  // operating change (a load or speed change moves the machine as a whole): it is followed (kind
  // level_step, not an alarm) only while its level stays within max_absorbed_ratio x its reference; a step
  // beyond that is judged as degradation. 1.5 = +3.5 dB: covers the +20-40 % single-channel steps of healthy
  // recordings, halfway (in dB) to warning_ratio, so a bearing that keeps rising in settled steps is caught
  // long before it doubles. Escalation to warning / critical is always judged against the reference (never
  // against a level a step rule adopted). After a recording gap each channel's reference becomes its level
  // before the gap times its own step, but at most the gap's common step (the median over the re-baselined
  // channels): the machine's re-levelling is carried into the reference, one channel's wear is not.
  double max_absorbed_ratio = 1.5;
  // Operating-state gate (log-transformed features, after the baseline): when EVERY channel's feature is
  // below stopped_ratio x its baseline median, the machine is not running (or the acquisition failed):
  // the observation says nothing about condition, so it is skipped and counted (no detector update).
  // 1/4 (-12 dB on all channels at once) mirrors critical_ratio; a fault raises one channel, it does not
  // silence all of them. 0 disables the gate.
  double stopped_ratio = 0.25;

  // ---------------------------------------------------------------- innovations ---------------------
  // innovation_rise: the CUSUM above on z = standardised e_k / sqrt(S_k) (or log mean NIS): channel k
  // does more than the other channels explain -> its OWN behaviour changed (drives the root cause).
  bool innovation_enabled = true;
  // innovation_nis: window mean of min(z^2, clip^2) over nis_window observations against the
  // chi-square(nis_window)/nis_window quantile at nis_false_alarm_prob (per observation).
  // One-sided by default (nis_two_sided = false): only positive departures (z > 0: more than the other
  // channels explain) enter, z^2 for z > 0 and 0 otherwise; the sum is then stochastically smaller than
  // the chi-square, so the false-alarm probability stays below nis_false_alarm_prob. Why one-sided: a
  // channel that becomes quieter than its causes predict (run-in, a healthy bearing that does not follow
  // a failing one) is not a fault; measured on IMS test 2, the two-sided window of bearing 2 (quietening
  // during run-in) reached 3.6 of 4.3 before the failure began.
  bool nis_enabled = true;
  bool nis_two_sided = false;
  int nis_window = 12;
  double nis_false_alarm_prob = 1e-6;
  // Severities of innovation and factor alarms from the current level in baseline sigmas (median of
  // the last level_window values): 6 sigma has a Gaussian tail probability of 1e-9 per observation,
  // i.e. the change is unambiguous even to a single look; 12 sigma is twice that.
  double warning_sigma = 6.0;
  double critical_sigma = 12.0;

  // ---------------------------------------------------------------- factor shift --------------------
  // factor_shift: max over the factors of outcome k of |x_i - baseline median_i| / sqrt(MAD-scale_i^2 +
  // std_i^2) against a Bonferroni two-sided Gaussian threshold at factor_false_alarm_prob per
  // observation, for factor_persistence consecutive observations (factor trajectories are random walks,
  // strongly autocorrelated, so consecutive exceedances are not independent evidence: the persistence
  // is a minimum duration, and the threshold carries the statistical weight).
  // OFF by default: the causal factors are random walks by model, so their spread over a short healthy
  // baseline says little about their later excursions, and a fixed-baseline test cannot be calibrated
  // (measured on IMS test 2 with the detector on: false factor_shift alarms on bearings 2 and 3 at
  // snapshots 243 and 271, from the slow run-in of those bearings). The factors are still tracked and
  // every alarm's explanation lists the ones that moved most.
  bool factor_enabled = false;
  double factor_false_alarm_prob = 1e-6;
  int factor_persistence = 6;

  // ---------------------------------------------------------------- root cause / explanation --------
  // Onsets (CUSUM change points) within this many index units (observations for a gap-free series) count
  // as simultaneous: the change-point estimate of a CUSUM is uncertain by about one to two observations
  // for shifts of 3 sigma or more.
  int onset_tolerance = 2;
  // Own-change evidence of a departure = z statistic of the mean standardised innovation since the
  // feature CUSUM's onset (sum / sqrt(n)); ~N(0,1) for a follower, whose rise the causal links explain.
  // A channel whose departure carries evidence >= own_evidence_z, or whose trouble began with its own
  // innovation_rise, is its OWN root cause when its change began clearly after the group's first root (a
  // second, independent fault, e.g. two failing bearings); otherwise the group's first root is blamed.
  // 3.72 = one-sided 1e-4: a follower is mistaken for an independent root once in 10^4 departures, i.e.
  // rarely even across a fleet of assets, each with a handful of departures per run-to-failure. (Late in
  // a failure the linear causal model under-explains followers -- propagation is nonlinear when the root
  // vibrates at several times its baseline -- so their innovations are not exactly N(0,1): a strict level
  // keeps them from being declared independent roots; measured on IMS test 2, bearing 2's departure at
  // snapshot 702, during bearing 1's largest jump, carries evidence 3.5.)
  double own_evidence_z = 3.72;
  // Factors listed in an alarm's explanation.
  int explain_top_factors = 3;

  // ---------------------------------------------------------------- gaps and operating changes -------
  // A level that moves because the machine was stopped or its duty changed is not a fault. Two situations
  // put the asset group under CONFIRMATION for confirmation_observations: every detector is held (no
  // update, no raise, no clear; active alarms stay active, and during a step's confirmation an active
  // feature_drift alarm of another channel keeps escalating on its own level) while the values are collected, then the
  // engine decides per channel and says so with an event of category "operating_change":
  //  * a discontinuity: Observation::discontinuity, the first observation after a stop (stopped_ratio
  //    gate), or a time gap larger than gap_multiple x the median interval of the baseline observations (IMS recorders stop for hours or days; levels after a restart
  //    differ by 15-20 % although nothing is wrong). Every channel without an active alarm is re-baselined
  //    (kind "discontinuity"): its feature location becomes the median of the confirmation window, unless
  //    the channel trends inside the window (progressive degradation does not pause for a gap: it keeps its
  //    old baseline and the detectors judge it). A channel with an active degradation alarm keeps its
  //    baseline: a fault does not heal during a gap.
  //  * an abrupt step: a feature CUSUM crosses its threshold within onset_tolerance + 1 observations of its
  //    onset AND the mean level since the onset is at least operating_step_ratio x the baseline median.
  //    Why a size: a change of load or speed changes the power through the machine and moves vibration
  //    levels by tens of percent from one record to the next; wear starts below the detection limit and
  //    its first significant departure is small (a few baseline sigmas: +7.5 % at IMS test 2's bearing-1
  //    onset; the operating changes are +15 % to +40 %). A smaller significant rise is alarmed at
  //    once, as before. After the window: a level that settled (kind "operating_change": no trend, see
  //    settle_trend_sigma) is re-baselined; one that keeps rising is progressive degradation and raises
  //    its feature_drift alarm then, with the onset at the step. Other channels whose level moved by a
  //    step as large in the same window and settled (a load change moves several bearings) are re-baselined
  //    with it. Gaps during the warm-up and baseline are not judged (the baseline is learned across them).
  //    Known limit: a step DOWN alone starts no confirmation (the detectors are upward): the channel keeps
  //    its higher baseline until a gap, a stop or another channel's step re-baselines it.
  // 12 observations = 2 h at the 10-minute IMS cadence: long enough for a robust slope (sd of the rise
  // over the window ~0.9 baseline sigma for 12 i.i.d. values), short against the days a bearing degrades.
  int confirmation_observations = 12;
  double gap_multiple = 3.0;
  double operating_step_ratio = 1.15;
  // Settled = the robust (Theil-Sen) rise of the log feature across the confirmation window is below this
  // many baseline sigmas: ~3.3 sd of that rise for i.i.d. noise, so a flat new level is almost never taken
  // for a trend, while a wear process that rises by more than 3 sigma in 2 h is.
  double settle_trend_sigma = 3.0;
  // Innovation locations are re-learned too after a re-baseline (upwards only: the filter's innovations
  // carry the level change until its factors adapt, which takes far longer than the window; a lower
  // location would make the one-sided detectors more sensitive than designed).

  // ---------------------------------------------------------------- escalation ---------------------
  // One event for the alarm and the forecast (AlarmEngine::level_event): warning (warning_ratio), critical
  // (critical_ratio) and end of life (the prognosis' end_of_life_ratio) are reached when the channel's level --
  // the median of the last level_window values over its reference -- has been at or above the multiple for
  // escalation_persistence consecutive observations. Every degradation alarm of a channel with a ratio scale
  // takes its severity from that event, and the prognosis says "reached" from it. 1: the median of 5 is
  // already a persistence (3 of 5 snapshots at the level, so one or two bursts cannot escalate), and a fast
  // final failure escalates within 2 snapshots of its first value at the level (12 made a bearing that
  // doubled in its last 4 snapshots end at advisory, and a forecast say "0 h" while the alarm waited).
  // Without a ratio scale (no log features) the kind's own level in sigmas must hold as long.
  int escalation_persistence = 1;

  // ---------------------------------------------------------------- root cause re-evaluation --------
  // The root cause of every active alarm is re-evaluated at every observation from the evidence
  // accumulated since its episode began: each departed channel's own-change evidence (z of the mean
  // standardised innovation since its departure, ChannelState::own_evidence) and its onset. When the named
  // root's own trouble is over (none of its alarms active, no own-change evidence left), a channel whose
  // evidence exceeds the named root's by root_cause_margin_z (the difference of two ~N(0,1)
  // statistics has sd sqrt(2): 3 sqrt(2) = 4.24 is one-sided 1e-3) for root_cause_persistence consecutive
  // observations takes over as root cause; the alarm is republished (state Escalated, same severity)
  // with the reason naming what changed. Confidence of an attribution = Phi((E_root - E_next) / sqrt(2)),
  // the probability that the named root's own-change statistic truly exceeds the runner-up's.
  double root_cause_margin_z = 4.24;
  int root_cause_persistence = 6;

  // Throws std::invalid_argument with a clear message when a value is out of range or when the
  // combination breaks a promise (e.g. a single spike could raise an alarm).
  void validate() const;

  // Decision interval h of the CUSUM detectors (Siegmund, from cusum_k and target_arl0).
  double cusum_threshold() const;
  // Raise threshold of innovation_nis on the window-mean clipped NIS.
  double nis_threshold() const;
  // Two-sided Bonferroni threshold of factor_shift for an outcome with `factor_count` factors.
  double factor_threshold(int factor_count) const;

  // Preset for sample-level factor publications (each observation summarises a block of raw samples):
  // the first `baseline_publications` publications (e.g. those of the healthy snapshots) are the warm-up
  // (one publication: the filter converges within its first block of thousands of samples) plus the
  // baseline; the innovation signal is then log mean NIS; NIS window 4 publications (a snapshot gives
  // ~20 publications of 1024 samples, so the window stays within one snapshot); the factor detector stays
  // off (see factor_enabled); time gaps are not discontinuities there (gap_multiple out of reach: the
  // publications come in bursts, one per snapshot).
  static AlarmParams sample_level(int baseline_publications);
};

// Checkpoint of every parameter, by name. restore() throws estimation::StateError on a truncated or foreign
// section, or when the saved names are not this build's (a parameter added or removed).
void save(estimation::StateWriter& out, const AlarmParams& params);
void restore(estimation::StateReader& in, AlarmParams& params);
// "name: a -> b" for every parameter whose value differs, comma-separated; empty when all are equal.
std::string param_differences(const AlarmParams& a, const AlarmParams& b);

}  // namespace causal::alarms
