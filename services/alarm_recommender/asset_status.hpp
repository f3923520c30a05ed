// One operator line per asset group (causal_twin/asset_status), built from the group's alarm
// engines after every observation. States, in this order of precedence:
//  * "alarm":    an open degradation alarm (either time scale): worst severity, its root cause, the latest advice;
//  * "stopped":  the latest observation was below the engine's operating-state gate (every channel under
//                AlarmParams::stopped_ratio x its baseline: the machine is not running). An operating state;
//  * "learning": the baseline is not learned yet (n of N observations): no verdict, so never "healthy";
//  * "healthy":  baseline learned, monitoring, nothing open.
// DDS-free apart from the generated type; the node publishes what update() reports as changed.
#pragma once

#include "causal/advice/alarm_desk.hpp"
#include "causal/alarms/alarm_engine.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <functional>
#include <utility>
#include <map>
#include <string>

namespace causal::recommender {

// The alarm desk's facts (the group's engines, the operating-state verdict, the prognosis line as a function, so
// the board stays free of the prognosis trends) and the alarm management desk's fields.
struct StatusInput : advice::StatusFacts {
  StatusInput() = default;
  explicit StatusInput(advice::StatusFacts facts) : advice::StatusFacts(std::move(facts)) {}
  // Fills the alarm management and health fields (unacknowledged, shelved, per 10 min, ...); unset: left 0.
  std::function<void(causal_twin::AssetStatus&)> management;
};

class AssetStatusBoard {
 public:
  // Computes the group's status; true (and `out` filled) when it differs from the last one reported, apart from
  // the index and time (a status is published when it changes, not at every snapshot).
  bool update(const std::string& group, const StatusInput& in, causal_twin::AssetStatus& out);
  // The advice given for an alarm (rank 1), shown while that alarm is the group's worst.
  void note_action(const std::string& alarm_id, const std::string& action) { actions_[alarm_id] = action; }
  // The group's last status with its management fields filled anew (after an operator action or an expired
  // shelving): true (and `out` filled) when they changed. False for a group with no status yet.
  bool refresh(const std::string& group, const std::function<void(causal_twin::AssetStatus&)>& management,
               causal_twin::AssetStatus& out);
  std::uint64_t published() const { return published_; }

 private:
  std::map<std::string, causal_twin::AssetStatus> last_;
  std::map<std::string, std::string> actions_;
  std::uint64_t published_ = 0;
};

}  // namespace causal::recommender
