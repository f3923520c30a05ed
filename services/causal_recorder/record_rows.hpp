// What causal-recorder writes for each topic: file names, headers and rows (cells already formatted;
// CsvFile quotes them). Kept out of the DDS node so the tests can check them without DDS.
#pragma once

#include "causal/dds/index_ledger.hpp"
#include "causal_twin.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace causal::recorder {

// conditions_<asset>_<feature>.csv and factors_<asset>_<scale>_<kind>.csv, with the ids sanitised
// ([A-Za-z0-9_.-] only). scale: sample | condition; kind: filter | fixed-lag | rts.
std::string conditions_file_name(const std::string& asset_group, const std::string& feature);
std::string factors_file_name(const std::string& asset_group, causal_twin::TimeScale scale,
                              causal_twin::EstimateKind kind);
inline constexpr const char* kAlarmsFile = "alarms.csv";
inline constexpr const char* kRecommendationsFile = "recommendations.csv";
inline constexpr const char* kPrognosisFile = "prognosis.csv";

// snapshot,time_ns,time_utc,<channel names...>
std::vector<std::string> condition_header(const causal_twin::ConditionVector& in);
std::vector<std::string> condition_row(const causal_twin::ConditionVector& in);

// The other recorded topics: header_of<M>() and row_of(m) (row_cells.hpp) from their field lists
// (causal/dds/message_fields.hpp), which twin-web reads back: alarms.csv, recommendations.csv, prognosis.csv,
// asset_status.csv, alarm_actions.csv, interventions.csv and intervention_outcomes.csv, in the historian the tables
// of the same names (MessageFields<M>::table). An alarm's row also needs its event time:
// time_utc is the data time of this state change: the clearing time for CLEARED, the raising time for
// RAISED, and for ESCALATED the time of sample_index when the caller knows it (evidence_time_ns, from the
// asset's condition-level factors), else empty. Times that are 0 ("not set") give empty cells.
std::vector<std::string> alarm_row(const causal_twin::Alarm& alarm, std::optional<std::int64_t> evidence_time_ns);

inline constexpr const char* kAssetStatusFile = "asset_status.csv";
// The recorder keeps every change of asset_status (the operator's line per asset group each time it changed):
// a KEEP_ALL reader (deploy/dds/qos.xml); views use asset_status_reader (last value per group). Named here, not in
// causal/dds/topics.hpp, as only the recorder reads the history.
inline constexpr const char* kAssetStatusHistoryReader = "asset_status_history_reader";
// alarm_actions.csv: one row per alarm action that alarm-recommender applied (causal_twin/alarm_action_result:
// acknowledge, shelve, unshelve, and shelvings that expired by themselves). Refused actions changed nothing: they
// are counted, not stored.
inline constexpr const char* kAlarmActionsFile = "alarm_actions.csv";

// Exactly once per key (asset group, channel, level) and snapshot: a prognosis whose sample_index is not
// after the last one written for its key is a repeat (transient-local replay, re-publication after a restart).
class PrognosisLedger {
 public:
  bool accept(const causal_twin::Prognosis& p);

 private:
  std::unordered_map<std::string, std::uint64_t> last_;
};

// Exactly once for the last-value topics (alarms, recommendations): a message whose signature equals the
// last one written for its id is a repeat (a transient-local replay to a re-matched reader, a re-send
// after a restart) and is not written again.
class RepeatFilter {
 public:
  // True when signature differs from the last one accepted for id (it is then the last one).
  bool accept(const std::string& id, std::string signature);
  std::size_t ids() const { return last_.size(); }

 private:
  std::unordered_map<std::string, std::string> last_;
};
// What makes an alarm message new: its state, severity and sample_index.
std::string alarm_signature(const causal_twin::Alarm& a);
// The cells of a row, joined: a row's signature where every recorded field makes a message new.
std::string row_signature(const std::vector<std::string>& row);
// A recommendation or an asset status is new unless every recorded field is the same (a repeat: a transient-local
// replay, a re-match).
std::string recommendation_signature(const causal_twin::Recommendation& r);
std::string asset_status_signature(const causal_twin::AssetStatus& s);

// What one recorded topic stream saw, for the exit log.
struct TopicCounts {
  std::uint64_t received = 0;
  std::uint64_t written = 0;
  std::uint64_t duplicates = 0;  // already written: not written again
  std::uint64_t refused = 0;     // did not fit the file (or were inconsistent)
  // Counts a message received and, unless is_new, a duplicate; returns is_new (write it).
  bool admit(bool is_new) {
    ++received;
    if (!is_new) ++duplicates;
    return is_new;
  }
};
// "received 12, written 9, duplicates 2, refused 1"
std::string describe(const TopicCounts& c);
// "lost snapshots 120..131, 140" ("" when nothing is missing); unit names the index ("snapshots").
std::string describe_missing(const std::vector<dds::IndexRange>& missing, const std::string& unit);

// Sample index -> UTC time of one asset's observation stream, so an alarm's sample_index can be placed
// in time. Keeps the newest `capacity` indices.
class IndexClock {
 public:
  explicit IndexClock(std::size_t capacity = 100000) : capacity_(capacity < 1 ? 1 : capacity) {}
  void record(std::uint64_t index, std::int64_t time_ns);
  std::optional<std::int64_t> time_of(std::uint64_t index) const;
  std::size_t size() const { return times_.size(); }

 private:
  std::size_t capacity_;
  std::map<std::uint64_t, std::int64_t> times_;
};

}  // namespace causal::recorder
