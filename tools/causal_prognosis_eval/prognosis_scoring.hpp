// Scoring of time-to-level predictions against known crossing times: the service's prognosis (causal_prognosis,
// fed exactly as alarm-recommender feeds it) and a baseline, a log-linear Theil-Sen trend since the alarm's
// onset with Sen's (1968) nonparametric slope interval, at every decision point from the channel's first
// degradation alarm on.
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

// Theil-Sen on (t hours, y log level over baseline) since the onset; y_now the last point's fitted level.
Prediction theil_sen_time_to(const std::vector<double>& t, const std::vector<double>& y, double log_ratio,
                             double coverage);

struct LevelScore {
  std::uint64_t decisions = 0;    // decision points with the level still ahead (truth)
  std::uint64_t known = 0;        // ... with a known interval
  std::uint64_t covered = 0;      // ... whose interval holds the actual time
  std::uint64_t reached_early = 0;  // said "reached" while it was not
  std::uint64_t truth_earlier = 0;  // known intervals that missed because the truth came before their low end
  std::vector<double> abs_errors;   // |median - actual| of the known ones, hours
  std::vector<double> widths;       // high - low of the known ones, hours
  void add(const Prediction& p, double actual_hours);
  void merge(const LevelScore& o);
};

struct MethodScores {
  std::array<LevelScore, kLevels> level;
};

// Runs an AlarmEngine and the channel trends over a stream of observations exactly as alarm-recommender does
// and scores channel `channel` against the crossing times truth_ns[level] (0 = not scored).
class PrognosisScorer {
 public:
  PrognosisScorer(std::unique_ptr<alarms::AlarmEngine> engine, prognosis::PrognosisParams params, int channel,
                  std::array<std::int64_t, kLevels> truth_ns);
  void observe(const alarms::Observation& obs);

  const MethodScores& twin() const { return twin_; }
  const MethodScores& baseline() const { return baseline_; }
  std::int64_t first_alarm_index() const { return first_alarm_index_; }  // -1 none
  double baseline_log() const { return baseline_log_; }                  // at the first alarm
  const alarms::AlarmEngine& engine() const { return *engine_; }
  // One line per decision point and level (for --trace): index, level, actual, both predictions.
  std::vector<std::string> trace;

 private:
  std::unique_ptr<alarms::AlarmEngine> engine_;
  prognosis::ChannelTrends trends_;
  int channel_;
  std::array<std::int64_t, kLevels> truth_ns_;
  MethodScores twin_, baseline_;
  std::int64_t first_alarm_index_ = -1;
  std::uint64_t onset_index_ = 0;
  double baseline_log_ = 0;
  std::vector<double> since_onset_t_, since_onset_y_;  // the baseline method's data
  std::vector<std::pair<std::uint64_t, std::pair<std::int64_t, double>>> history_;  // index, time, log feature
};

struct SimRun;  // run_to_failure_sim.hpp

// Channel 0 of a simulated run scored as alarm-recommender would see it (a fresh engine with the default alarm
// parameters), against the run's crossings of 2x, 4x and params.end_of_life_ratio x its baseline.
PrognosisScorer score_simulated_run(const SimRun& run, const prognosis::PrognosisParams& params);

// "level  method  decisions  known%  coverage(known)  coverage(all)  median|err| h" table rows.
std::string score_table(const std::string& title, const MethodScores& twin, const MethodScores& baseline);

}  // namespace causal::prognosis_eval
