// Per-group grants for a writer's life, for every service that reads an input topic written by outside identities
// (causal-estimator: sensor frames and condition inputs; alarm-recommender: what-if requests). A remote writer may
// write a sample of an asset group only when the partitions of its FIRST discovery name that group
// (group_partitions.hpp: partitions_allow_group); a writer that announced other partitions later is refused from
// then on, for every group: Fast DDS 2.9 keeps the match of a writer that moves (Publisher::set_qos) to
// partitions its grant does not name and only logs "partition not found in rule", so the writer's later
// announcement is never its grant (ParticipantDirectory::writer_partitions_changed). A writer never discovered
// cannot be checked and is refused like one without the grant.
//
// Each refusal is counted; the first of each writer and group (at most kMaxPairs) is logged and turned into a
// HEALTH alarm (category "health", CRITICAL, kind "group_not_entitled", id "<group>/<part>/group_not_entitled/
// t<seconds>.<serial>") naming the writer's GUID and its participant. The service writes the alarms, counts the
// refusals in its summary and exits 4 (nothing refused silently).
#pragma once

#include "causal/dds/participant.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace causal::dds {

class WriterGrantCheck {
 public:
  // part: the alarm id's part naming what was refused ("input", "whatif"); what: the same for the reasons
  // ("input", "what-if request"); who_is_granted: how such identities get their groups, for the operator.
  WriterGrantCheck(const ParticipantDirectory& directory, std::string part, std::string what,
                   std::string who_is_granted);

  // Whether `writer` may write a sample of `asset_group`. false: counted, and on the first refusal of this writer
  // and group logged and a HEALTH alarm queued (take_alarms).
  bool entitled(const std::string& asset_group, const eprosima::fastrtps::rtps::GUID_t& writer);

  std::uint64_t refused() const { return refused_; }
  std::size_t refused_pairs() const { return pairs_.size(); }  // writer and group pairs alarmed
  // The HEALTH alarms raised since the last call.
  std::vector<causal_twin::Alarm> take_alarms();

  static constexpr std::size_t kMaxPairs = 1024;  // a writer that tries every group cannot grow the set further

 private:
  std::string reason(const eprosima::fastrtps::rtps::GUID_t& writer, const std::string& who) const;

  const ParticipantDirectory& directory_;
  std::string part_, what_, who_is_granted_;
  std::uint64_t refused_ = 0;
  std::set<std::string> pairs_;  // "writer|group"
  std::vector<causal_twin::Alarm> alarms_;
};

}  // namespace causal::dds
