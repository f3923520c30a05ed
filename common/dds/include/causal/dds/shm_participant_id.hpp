// The participant id of a process that uses Fast DDS 2.9's shared-memory transport, chosen so that the process
// never listens on a shared-memory port whose old segment a live peer still has open.
//
// Why: a participant listens on the shared-memory port of its id (PortParameters: 7400 + 250 domain + 11 + 2 id
// for user traffic) and Fast DDS gives every process id 0, moving on by 2 ports while a port is taken. A port whose
// reader died (SIGKILL) counts as free: Fast DDS removes its segment and creates a new one, but does not mark the
// old one bad (fixed upstream in Fast DDS pull request 4728, not in Debian's 2.9.1), and a peer that had the old
// segment open caches it by port number for ever; its port watchdog only notices a reader that died while
// waiting, not one killed while it was taking a message. That peer then writes into the removed segment:
// discovery (UDP) keeps the new process matched, and nothing it is sent over shared memory arrives
// (docs/reliability.md "Shared memory and SIGKILL").
// What: the lowest id whose ports are safe to listen on (shm_port_safe_to_listen) is set explicitly in the
// participant QoS, under a host-wide lock held until the participant exists, so two processes starting at once do
// not both pick it and the loser is not moved by Fast DDS onto an unsafe port. Participants without a
// shared-memory transport, and profiles that set the id or the listening locators themselves, are left alone.
#pragma once

#include <fastdds/dds/core/status/StatusMask.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace causal::dds {

// One shared-memory port as this host shows it: the segment <shm_dir>/fastrtps_port<P>, the exclusive-reader
// lock file fastrtps_port<P>_el (flock-ed by the live reader), and the segments of that name live processes have
// mapped (/proc/<pid>/maps; a removed one is still mapped by whoever had it open).
struct ShmPortState {
  bool reader_alive = false;              // the lock file is locked: a live process listens on the port
  bool reader_dead = false;               // the lock file exists unlocked: Fast DDS replaces the segment on open
  std::optional<std::uint64_t> segment;   // inode of the current segment file, if there is one
  std::set<std::uint64_t> mapped;         // inodes of this port's segments mapped by live processes
};

// Whether a new participant may listen on the port: no live reader holds it, and every live mapping of the
// port is of the segment the new participant will read (the current one, unless a dead reader's segment is
// about to be replaced). A dead reader's port that nobody has mapped any more is safe: Fast DDS's replacement
// leaves no one behind.
bool shm_port_safe_to_listen(const ShmPortState& port);

// Reads the state of `ports` from `shm_dir` and from the maps of the processes in `proc_dir` (only mappings on
// the device of shm_dir count: another mount namespace's /dev/shm is another device).
std::map<std::uint32_t, ShmPortState> read_shm_ports(const std::vector<std::uint32_t>& ports,
                                                      const std::string& shm_dir = "/dev/shm",
                                                      const std::string& proc_dir = "/proc");

// The shared-memory ports a participant listens on, by id (Fast DDS's well-known port mapping).
struct ShmListenPorts {
  std::uint32_t base = 7400;
  std::uint32_t domain_gain = 250;
  std::uint32_t id_gain = 2;
  std::uint32_t user_offset = 11;  // offsetd3: default unicast (user traffic)
  std::uint32_t meta_offset = 10;  // offsetd1: metatraffic unicast
  bool user = true;                // shared memory carries user traffic on the default port
  bool metatraffic = false;        // ... and metatraffic (no metatraffic locators given, or SHM ones)
  std::vector<std::uint32_t> of(int domain, int id) const;
};

struct ShmIdChoice {
  int participant_id = -1;                 // -1: none safe below max_ids, Fast DDS chooses
  std::vector<std::uint32_t> passed_over;  // unsafe ports of the lower ids not taken by this process
};

// The lowest id in [0, max_ids), not in `in_process` (ids of this process's participants: Fast DDS refuses a
// second participant with one), all of whose ports `safe` accepts.
ShmIdChoice choose_participant_id(const ShmListenPorts& ports, int domain, int max_ids, const std::set<int>& in_process,
                                  const std::function<bool(std::uint32_t)>& safe);

// The host-wide lock of the choice (<shm_dir>/causal_twin_ids_d<domain>.lock, flock): taken by
// assign_shm_participant_id, released once the participant has opened its ports (release() or destruction).
class ShmChoiceLock {
 public:
  ShmChoiceLock() = default;
  ~ShmChoiceLock() { release(); }
  ShmChoiceLock(const ShmChoiceLock&) = delete;
  ShmChoiceLock& operator=(const ShmChoiceLock&) = delete;
  // Waits up to 10 s for the lock; false (and not held) when it could not be had.
  bool acquire(const std::string& shm_dir, int domain);
  void release();

 private:
  int fd_ = -1;
};

// What assign_shm_participant_id did.
struct ShmIdAssignment {
  int participant_id = -1;            // the id set in the QoS; -1: left to Fast DDS
  std::vector<std::uint32_t> ports;   // the shared-memory ports that id listens on
  std::string note;                   // for the log; empty when there is nothing to say
  bool warning = false;               // the note is a warning (no safe id, no lock)
};

// Sets qos.wire_protocol().participant_id when the participant has a shared-memory transport, listens on the
// default ports and leaves the id to Fast DDS (-1), holding `lock` from the choice on; otherwise changes nothing.
ShmIdAssignment assign_shm_participant_id(eprosima::fastdds::dds::DomainParticipantQos& qos, int domain,
                                          ShmChoiceLock& lock, const std::string& shm_dir = "/dev/shm");

// Whether this process holds the exclusive-reader lock of shared-memory port `port` (/proc/locks): after
// creation, whether the participant got the port it was given.
bool listens_on_shm_port(std::uint32_t port, const std::string& shm_dir = "/dev/shm");

// Whether the choice is on: $CAUSAL_TWIN_SHM_PORT_CHOICE=1. Off by default: with it on, a recommender killed and
// restarted at once in AlarmRestart (tests/integration/test_alarm_restart.cpp) counted samples lost (DDS
// sample-lost status, exit 4) in 5 of 7 runs, 0 of 4 without it; not understood yet (docs/reliability.md
// "Shared memory and SIGKILL").
bool shm_port_choice_enabled();

// DomainParticipantFactory::create_participant with the id assign_shm_participant_id chooses when enabled (the lock held until
// the participant exists): logs the note, and warns when the participant does not listen on the ports it was given
// (a process that does not take the lock took one at the same moment, and Fast DDS moved on).
eprosima::fastdds::dds::DomainParticipant* create_participant_on_safe_shm_port(
    int domain, eprosima::fastdds::dds::DomainParticipantQos qos, eprosima::fastdds::dds::DomainParticipantListener* listener,
    const eprosima::fastdds::dds::StatusMask& mask);

}  // namespace causal::dds
