// The verdict a plant engineer reads first: per asset group, is it failing, since when, why, and what to do.
// Built from a causal-recorder folder (alarms.csv, recommendations.csv); printed by causal-report at the end of
// every run (launch.sh, demo.sh) and put at the top of report_<asset>.md.
//
// Rules (stated in the README):
//  * only degradation alarms decide the status; data-quality, health and operating-change events are counted
//    beside it (they are about the measurement or the operation, not the machine);
//  * status = the highest severity among the degradation alarms still open at the end of the recording
//    (CRITICAL / WARNING / ADVISORY), "recovered" when alarms were raised and all cleared, else "healthy";
//  * first alarm = the earliest raised degradation alarm (UTC time, channel, detector, the source's index);
//  * root cause = the root named by the latest row of the open alarms at the highest severity (the engine
//    re-evaluates it), with its confidence when recorded;
//  * top recommendation = the latest rank-1 recommendation of the asset whose interval excludes no effect
//    (reliable); when none is reliable, the latest rank-1 text, which says why there is no reliable lever;
//  * prognosis (prognosis.csv) = while an alarm is open: the root cause's (else the worst alarm's channel's)
//    next level above the worst open severity (WARNING: critical, CRITICAL: end_of_life) not yet reached, as
//    its latest prognosis says it (hours, interval, UTC), or why it is unknown.
#pragma once

#include "run_data.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace causal::report {

struct RecommendationRecord {
  std::string recommendation_id, alarm_id, asset_group, text, summary, answer_kind;
  std::string action, action_kind;  // the decision columns; empty in older recordings
  std::string sample_index;         // the alarm event it answers; empty in older recordings
  int rank = 0;
  bool reliable = true;  // older recordings have no such column: their advice is taken as given
};

struct PrognosisRecord {
  std::string asset_group, channel_name, level, text;
  double sample_index = 0.0;
  bool known = false, reached = false;
};

// Rows of prognosis.csv for `asset` (sanitised id; all rows when empty), in file order.
std::vector<PrognosisRecord> load_prognoses(const std::filesystem::path& file, const std::string& asset);

// Rows of recommendations.csv for `asset` (sanitised id; all rows when empty), in file (publication) order.
std::vector<RecommendationRecord> load_recommendations(const std::filesystem::path& file, const std::string& asset);

struct AssetVerdict {
  std::string asset;
  std::string status;              // CRITICAL, WARNING, ADVISORY, recovered, healthy
  std::string first_alarm;         // "2004-02-16 03:22:39 bearing1 feature_drift (index 533)" or "-"
  std::string root_cause;          // "bearing1 (confidence 0.93)" or "-"
  std::string root_cause_note;     // why a low confidence is low (the alarm reason's "Attribution confidence ..."), or ""
  std::string top_recommendation;  // one line, or "-": the latest action (at its alarm event's index) when the
                                   // recording has actions, else the best rank-1 text
  std::string events;              // "2 operating changes, 1 data quality" or ""
  std::string prognosis;           // "bearing1 reaches critical (4x its baseline) in 1.0 h (...)" or "" (no alarm open
                                   // or no prognosis recorded)
};

AssetVerdict verdict_of(const std::string& asset, const std::vector<AlarmRecord>& alarms,
                        const std::vector<RecommendationRecord>& recommendations,
                        const std::vector<PrognosisRecord>& prognoses = {});

// A fixed-width table with one row per asset (the top recommendation on its own indented line).
std::string verdict_table(const std::vector<AssetVerdict>& verdicts);

}  // namespace causal::report
