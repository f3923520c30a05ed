// Scoring of time-to-level predictions against known crossing times: the service's prognosis (causal_prognosis,
// fed exactly as alarm-recommender feeds it) and two anchors on the same data (prognosis_anchors.hpp: a
// log-linear Theil-Sen trend with bootstrap intervals, a random walk with drift and its inverse-Gaussian first
// passage), at every decision point from the channel's first degradation alarm on. The event scored is the
// alarm's own: the first snapshot whose trailing 5-snapshot median of the channel's level reaches the level's
// multiple of the healthy reference (median_crossings).
#pragma once

#include "causal/alarms/alarm_engine.hpp"
#include "causal/prognosis/alarm_prognosis.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace causal::prognosis_eval {

inline constexpr int kLevels = 3;  // prognosis::Level::warning, critical, end_of_life

// One prediction of the hours to a level (either method).
struct Prediction {
  bool known = false, reached = false;
  double hours = 0, low = 0, high = 0;
  std::string why;  // when unknown
};

inline constexpr int kMedianWindow = 5;  // snapshots of the trailing median that judges "reached"

// Per level, the time of the first snapshot i >= from whose trailing median of values[i-4..i] is at or above
// ratios[l] * reference (0 = never). A level never reached before stop_index gets the stop's time when
// stop_index >= 0 (the end of a run to failure), else 0 (not scored). index_out: the snapshot (-1 none).
std::array<std::int64_t, kLevels> median_crossings(const std::vector<std::int64_t>& time_ns,
                                                   const std::vector<double>& values, double reference,
                                                   std::int64_t from, const std::array<double, kLevels>& ratios,
                                                   std::int64_t stop_index,
                                                   std::array<std::int64_t, kLevels>* index_out = nullptr);

struct LevelScore {
  std::uint64_t decisions = 0;    // decision points with the level still ahead (truth)
  std::uint64_t known = 0;        // ... answered (a known interval, or "reached")
  std::uint64_t covered = 0;      // ... whose interval holds the actual time
  std::uint64_t reached_early = 0;  // said "reached" while it was not
  std::uint64_t truth_earlier = 0;  // answers that missed because the truth came before their low end
  std::uint64_t within_20 = 0, within_30 = 0;  // alpha-lambda: |median - actual| <= 0.2 / 0.3 actual
  std::vector<double> abs_errors;   // |median - actual| of the answered ones, hours
  std::vector<double> rel_widths;   // (high - low) / actual of the answered ones
  void add(const Prediction& p, double actual_hours);
  void merge(const LevelScore& o);
};

// twin, Theil-Sen with bootstrap, random walk with drift, the twin's long-run model alone (excess_growth.hpp),
// and conformal intervals on the channel's own level forecasts (prognosis_conformal.hpp)
inline constexpr int kMethods = 5;
const char* method_name(int method);

struct MethodScores {
  std::array<LevelScore, kLevels> level;
  void merge(const MethodScores& o);
};

// Runs an AlarmEngine and the channel trends over a stream of observations exactly as alarm-recommender does
// and scores channel `channel` against the crossing times truth_ns[level] (0 = not scored).
class PrognosisScorer {
 public:
  PrognosisScorer(std::unique_ptr<alarms::AlarmEngine> engine, prognosis::PrognosisParams params, int channel,
                  std::array<std::int64_t, kLevels> truth_ns);
  void observe(const alarms::Observation& obs);

  const MethodScores& twin() const { return scores_[0]; }
  const MethodScores& theil_sen() const { return scores_[1]; }
  const MethodScores& random_walk() const { return scores_[2]; }
  const std::array<MethodScores, kMethods>& scores() const { return scores_; }
  std::int64_t first_alarm_index() const { return first_alarm_index_; }  // -1 none
  double baseline_log() const { return baseline_log_; }                  // at the first alarm
  const alarms::AlarmEngine& engine() const { return *engine_; }
  // One line per decision point and level (for --trace): index, level, actual, the predictions.
  std::vector<std::string> trace;

 private:
  std::unique_ptr<alarms::AlarmEngine> engine_;
  prognosis::ChannelTrends trends_;
  int channel_;
  std::array<std::int64_t, kLevels> truth_ns_;
  std::array<MethodScores, kMethods> scores_;
  std::int64_t first_alarm_index_ = -1;
  std::uint64_t onset_index_ = 0;
  double baseline_log_ = 0;
  std::vector<std::pair<std::uint64_t, std::pair<std::int64_t, double>>> history_;  // index, time, log feature
};

struct SimRun;  // run_to_failure_sim.hpp

// Channel 0 of a simulated run scored as alarm-recommender would see it (a fresh engine with the default alarm
// parameters), against the first crossings of 2x, 4x and params.end_of_life_ratio x the engine's baseline at
// the first alarm by the trailing 5-snapshot median of the observed level (the stop when one is never reached).
PrognosisScorer score_simulated_run(const SimRun& run, const prognosis::PrognosisParams& params);

// Per level and method: decisions, share answered, coverage of the 90 % intervals (answered ones), median
// interval width over the actual remaining time, alpha-lambda at +-20 % and +-30 % (all decision points: an
// unknown is not within), share of the misses with the truth before the interval.
std::string score_table(const std::string& title, const std::array<MethodScores, kMethods>& scores);

}  // namespace causal::prognosis_eval
