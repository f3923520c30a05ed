// DDS side of SourceHealth: remembers which participant wrote each source's (asset group's) last sample, turns
// that participant's departure into "ended cleanly" (it left saying goodbye: REMOVED_PARTICIPANT) or "writer
// lost" (its lease expired: DROPPED_PARTICIPANT, e.g. a killed sensor), and the health changes into HEALTH
// alarms on causal_twin/alarm (category "health", severity WARNING), id "<group>/<watched>/health/s<last
// snapshot>" (causal-estimator: "source", its input; alarm-recommender: "estimator", the causal factors;
// distinct, since both can be silent at once). The service writes the alarms and decides what to log.
//
// Why a wall-clock check in the service and not the DDS Deadline QoS: QoS lives in deploy/dds/qos.xml only,
// and a reader's requested deadline must be matched by every writer's offered one (else they never match),
// so every source would have to ship the same period; the missed-deadline status also names only the last
// instance, not every silent one, and never says when the source is back. The deadline is a key of the
// service's parameter file instead (health.deadline_s).
//
// Why participant departures and not the instance states (NOT_ALIVE_DISPOSED / NOT_ALIVE_NO_WRITERS): with
// Fast DDS 2.9 and our RELIABLE, KEEP_ALL, TRANSIENT_LOCAL profiles, take_next_sample never returned a
// data-less sample for either (a disposed instance, a writer that left), the readers never acknowledged a
// dispose, and an estimator that disposed its 1024 factor instances at exit took 10 s to leave while a
// counting reader received 23808 factor messages instead of the 8192 sent (tests/fault). So no writer
// disposes; departures are reported by discovery for every participant. on_state() still handles instance
// states, for a Fast DDS that hands them out.
#pragma once

#include "causal/dds/participant.hpp"
#include "causal/dds/source_health.hpp"
#include "causal_twin.h"

#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace causal::dds {

class HealthWatch {
 public:
  // what: the watched input, for the reasons ("frames/condition inputs", "causal factors"); watched: the
  // alarm id's part naming who is silent ("source", "estimator"); topics: the topics read. A lost writer
  // raises at once only when no other writer of these topics is alive; otherwise (a restarted source already
  // back, a hot standby about to take over) the deadline decides, so a recovery within it raises nothing.
  HealthWatch(double deadline_s, std::string what, std::string watched, std::vector<std::string> topics);

  // A valid sample of `source` (snapshot index of the source, when the sample has one).
  void on_sample(const std::string& source, std::uint64_t snapshot_index,
                 const eprosima::fastdds::dds::SampleInfo& info);
  void on_sample(const std::string& source, const eprosima::fastdds::dds::SampleInfo& info);
  // A sample without data (valid_data false): the instance was disposed or lost its writers.
  void on_state(const eprosima::fastdds::dds::SampleInfo& info);
  // Departures of writers' participants, then the deadline check; the run loop calls it at every wake-up.
  void check(const ParticipantDirectory& directory);
  // The alarm messages (raised and cleared) since the last call.
  std::vector<causal_twin::Alarm> take_alarms();

  const SourceHealth& health() const { return health_; }
  std::uint64_t unknown_instances() const { return unknown_instances_; }  // state change of an instance never seen

 private:
  void convert(std::vector<HealthChange>& changes);

  SourceHealth health_;
  std::string what_, watched_;
  std::vector<std::string> topics_;
  std::map<std::array<unsigned char, 16>, std::string> sources_;  // instance handle -> source
  std::map<std::string, eprosima::fastrtps::rtps::GuidPrefix_t> writers_;  // source -> participant of its last sample
  std::size_t departures_seen_ = 0;
  std::vector<ParticipantDirectory::Departure> departures_;
  std::map<std::string, causal_twin::Alarm> open_;                // source -> its raised alarm
  std::vector<HealthChange> changes_;
  std::vector<causal_twin::Alarm> alarms_;
  std::uint64_t unknown_instances_ = 0;
};

}  // namespace causal::dds
