// The estimator's data-quality alarms (Alarm.category "data_quality"): what the input screen found in one
// asset group's data (common/pipeline/input_screen.hpp), as alarms on causal_twin/alarm, so a bad value or a
// dead channel is visible to the operator, not only in a log.
//  * bad values (non_finite, out_of_range): an ADVISORY alarm per channel and kind, raised at the first bad
//    value and cleared at the end of the first snapshot without one;
//  * a quarantined channel (stuck, scale_change): a WARNING alarm, cleared when the screen releases it;
//  * input the estimator refuses (a model that does not fit the group, an unusable checkpoint, a fault in the
//    estimation): one CRITICAL alarm "input_refused" per asset group, raised at the first refused input and
//    never cleared (the group's data is not being analysed; the estimator exits 4).
//  * the machine stopped (every channel at the quantisation floor, input_screen.hpp): an "operating_change" event
//    "machine_stopped" (ADVISORY), open while it stands, cleared when the channels are live again. Not a fault.
// Ids are "<asset group>/<channel>/<kind>/s<snapshot index>" (the snapshot it was raised in, from the source;
// the raw-frame screen: "<asset group>/sample/<channel>/<kind>/s<n>", as the sample-level alarm engines; the
// group's input: "<group>/input/..",
// the machine: "<group>/machine/machine_stopped/s<n>"), with ".2", ".3" when one id would be raised twice in a
// snapshot: deterministic, and never reused after a restart.
#pragma once

#include "causal/pipeline/input_screen.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace causal::estimator {

class DataQualityAlarms {
 public:
  // Appends the alarm messages (raised / cleared) the screen's events of one frame or vector cause.
  void on_events(const std::string& asset_group, const std::vector<std::string>& channel_names,
                 const std::vector<pipeline::QualityEvent>& events, std::uint64_t snapshot_index, std::int64_t time_ns,
                 std::vector<causal_twin::Alarm>& out);
  // At the end of a snapshot: clears the bad-value alarms of this group that saw no bad value in it.
  void end_of_snapshot(const std::string& asset_group, std::uint64_t snapshot_index, std::int64_t time_ns,
                       std::vector<causal_twin::Alarm>& out);
  // A refused input of this group: appends the input_refused alarm the first time; true when it did.
  bool on_refused(const std::string& asset_group, const std::string& reason, std::uint64_t snapshot_index,
                  std::int64_t time_ns, std::vector<causal_twin::Alarm>& out);
  std::uint64_t raised() const { return raised_; }
  std::uint64_t machine_stops() const { return stopped_; }

 private:
  // machine_stopped / machine_running: the operating_change event "machine_stopped", open while the machine stands.
  void on_operating_state(const std::string& asset_group, const pipeline::QualityEvent& e,
                          std::uint64_t snapshot_index, std::int64_t time_ns, std::vector<causal_twin::Alarm>& out);
  std::string unique_id(const std::string& id);
  struct Open {
    causal_twin::Alarm msg;
    bool bad_value = false;     // cleared by a clean snapshot (else by a recovery event)
    bool seen_in_snapshot = false;
  };
  std::map<std::string, Open> open_;  // by "<group>\x1f<channel>\x1f<alarm kind>"
  // Publishes the open alarm as CLEARED (at this snapshot, with this reason) and forgets it; the next one.
  std::map<std::string, Open>::iterator clear(std::map<std::string, Open>::iterator it, std::uint64_t snapshot_index,
                                              std::int64_t time_ns, const std::string& reason,
                                              std::vector<causal_twin::Alarm>& out);
  // The same by key; nothing when no such alarm is open.
  void clear(const std::string& key, std::uint64_t snapshot_index, std::int64_t time_ns, const std::string& reason,
             std::vector<causal_twin::Alarm>& out);
  std::map<std::string, std::uint64_t> issued_;  // ids raised by this process (never raised twice)
  std::uint64_t raised_ = 0, stopped_ = 0;
};

}  // namespace causal::estimator
