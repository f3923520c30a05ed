#include "causal/dds/shm_participant_id.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/rtps/common/Locator.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace causal::dds {

namespace {

constexpr const char* kPortPrefix = "fastrtps_port";  // Fast DDS 2.9: SHM_MANAGER_DOMAIN "fastrtps" + "_port"
constexpr int kDefaultMaxIds = 32;  // the loopback profiles' maxInitialPeersRange
constexpr int kMaxDomain = 232;

std::string port_file(const std::string& shm_dir, std::uint32_t port) {
  return shm_dir + "/" + kPortPrefix + std::to_string(port);
}

// The exclusive-reader lock file: locked (flock) by the live reader; present and unlocked after it died.
void read_reader_lock(const std::string& shm_dir, std::uint32_t port, ShmPortState& state) {
  const std::string lock = port_file(shm_dir, port) + "_el";
  const int fd = ::open(lock.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    // Absent: no reader ever held the port, or it left cleanly. Unreadable: not ours to judge, not safe.
    if (errno != ENOENT) state.reader_alive = true;
    return;
  }
  // A shared lock, released at once: fails only while a reader holds its exclusive one.
  if (::flock(fd, LOCK_SH | LOCK_NB) == 0) {
    state.reader_dead = true;
    ::flock(fd, LOCK_UN);
  } else {
    state.reader_alive = true;
  }
  ::close(fd);
}

// "fastrtps_port7413" or "fastrtps_port7413 (deleted)" at the end of a maps line -> 7413.
std::optional<std::uint32_t> mapped_port(const std::string& path, const std::string& prefix) {
  if (path.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  std::size_t i = prefix.size();
  std::uint64_t port = 0;
  const std::size_t digits_from = i;
  while (i < path.size() && path[i] >= '0' && path[i] <= '9' && i - digits_from < 6) {
    port = port * 10 + static_cast<std::uint64_t>(path[i] - '0');
    ++i;
  }
  if (i == digits_from || port > 65535) return std::nullopt;
  const std::string rest = path.substr(i);
  if (!rest.empty() && rest != " (deleted)") return std::nullopt;
  return static_cast<std::uint32_t>(port);
}

// One line of /proc/<pid>/maps: "start-end perms offset MAJ:MIN inode   path".
void read_maps_line(const std::string& line, const std::string& prefix, dev_t device,
                    std::map<std::uint32_t, ShmPortState>& states) {
  const auto at = line.find(prefix);
  if (at == std::string::npos) return;
  std::istringstream in(line.substr(0, at));
  std::string range, perms, offset, dev;
  std::uint64_t inode = 0;
  if (!(in >> range >> perms >> offset >> dev >> inode)) return;
  const auto colon = dev.find(':');
  if (colon == std::string::npos) return;
  const unsigned long maj = std::strtoul(dev.substr(0, colon).c_str(), nullptr, 16);
  const unsigned long min = std::strtoul(dev.substr(colon + 1).c_str(), nullptr, 16);
  if (maj != major(device) || min != minor(device)) return;
  const auto port = mapped_port(line.substr(at), prefix);
  if (!port) return;
  const auto it = states.find(*port);
  if (it != states.end()) it->second.mapped.insert(inode);
}

}  // namespace

bool shm_port_safe_to_listen(const ShmPortState& port) {
  if (port.reader_alive) return false;
  if (port.reader_dead) return port.mapped.empty();  // its segment is replaced: any mapping of it goes stale
  for (const std::uint64_t inode : port.mapped) {
    if (!port.segment || inode != *port.segment) return false;  // a removed segment someone still writes into
  }
  return true;
}

std::map<std::uint32_t, ShmPortState> read_shm_ports(const std::vector<std::uint32_t>& ports,
                                                      const std::string& shm_dir, const std::string& proc_dir) {
  std::map<std::uint32_t, ShmPortState> states;
  struct stat dir {};
  if (::stat(shm_dir.c_str(), &dir) != 0) return states;
  for (const std::uint32_t port : ports) {
    ShmPortState& state = states[port];
    read_reader_lock(shm_dir, port, state);
    struct stat segment {};
    if (::stat(port_file(shm_dir, port).c_str(), &segment) == 0 && segment.st_dev == dir.st_dev) {
      state.segment = static_cast<std::uint64_t>(segment.st_ino);
    }
  }
  // The kernel writes the resolved path into maps.
  std::error_code ec;
  const std::string prefix = std::filesystem::canonical(shm_dir, ec).string() + "/" + kPortPrefix;
  if (ec) return states;
  for (const auto& entry : std::filesystem::directory_iterator(proc_dir, ec)) {
    const std::string pid = entry.path().filename().string();
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream maps(entry.path() / "maps");  // unreadable (another user's process): skipped
    for (std::string line; std::getline(maps, line);) read_maps_line(line, prefix, dir.st_dev, states);
  }
  return states;
}

std::vector<std::uint32_t> ShmListenPorts::of(int domain, int id) const {
  const auto at = [&](std::uint32_t offset) {
    return base + domain_gain * static_cast<std::uint32_t>(domain) + offset + id_gain * static_cast<std::uint32_t>(id);
  };
  std::vector<std::uint32_t> out;
  if (metatraffic) out.push_back(at(meta_offset));
  if (user) out.push_back(at(user_offset));
  return out;
}

ShmIdChoice choose_participant_id(const ShmListenPorts& ports, int domain, int max_ids, const std::set<int>& in_process,
                                  const std::function<bool(std::uint32_t)>& safe) {
  ShmIdChoice choice;
  for (int id = 0; id < max_ids; ++id) {
    if (in_process.count(id) > 0) continue;
    const auto candidate = ports.of(domain, id);
    if (std::any_of(candidate.begin(), candidate.end(), [](std::uint32_t p) { return p > 65535; })) break;
    bool all_safe = true;
    for (const std::uint32_t p : candidate) {
      if (!safe(p)) {
        all_safe = false;
        choice.passed_over.push_back(p);
      }
    }
    if (all_safe) {
      choice.participant_id = id;
      return choice;
    }
  }
  return choice;
}

bool ShmChoiceLock::acquire(const std::string& shm_dir, int domain) {
  release();
  const std::string path = shm_dir + "/causal_twin_ids_d" + std::to_string(domain) + ".lock";
  fd_ = ::open(path.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0666);
  if (fd_ < 0) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    if (std::chrono::steady_clock::now() >= deadline) {
      release();
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

void ShmChoiceLock::release() {
  if (fd_ >= 0) ::close(fd_);  // closing the only descriptor drops the flock
  fd_ = -1;
}

namespace {

using eprosima::fastdds::dds::DomainParticipantQos;

// The ids of this process's participants (all domains: Fast DDS keeps one set per process): GUID prefix bytes
// 8..11 are the participant id, little endian.
std::set<int> ids_in_this_process() {
  std::set<int> ids;
  auto* factory = eprosima::fastdds::dds::DomainParticipantFactory::get_instance();
  for (int domain = 0; domain <= kMaxDomain; ++domain) {
    for (const auto* p : factory->lookup_participants(static_cast<eprosima::fastdds::dds::DomainId_t>(domain))) {
      const auto& v = p->guid().guidPrefix.value;
      ids.insert(static_cast<int>(v[8] | (v[9] << 8) | (v[10] << 16) | (static_cast<unsigned>(v[11]) << 24)));
    }
  }
  return ids;
}

// Which ports the participant listens on over shared memory and how many ids discovery reaches; nullopt when
// it has no shared-memory transport or chooses its listening locators itself.
std::optional<std::pair<ShmListenPorts, int>> shm_listen_ports(const DomainParticipantQos& qos) {
  const auto& wire = qos.wire_protocol();
  if (wire.participant_id >= 0) return std::nullopt;
  if (!wire.default_unicast_locator_list.empty() || !wire.default_multicast_locator_list.empty()) return std::nullopt;
  bool shm = qos.transport().use_builtin_transports;  // Fast DDS's built-in transports include shared memory
  std::uint32_t range = 0;
  for (const auto& descriptor : qos.transport().user_transports) {
    if (std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(descriptor)) {
      shm = true;
    } else if (descriptor) {
      range = std::max(range, descriptor->max_initial_peers_range());
    }
  }
  if (!shm) return std::nullopt;
  ShmListenPorts ports;
  ports.base = wire.port.portBase;
  ports.domain_gain = wire.port.domainIDGain;
  ports.id_gain = wire.port.participantIDGain;
  ports.user_offset = wire.port.offsetd3;
  ports.meta_offset = wire.port.offsetd1;
  const auto& meta = wire.builtin.metatrafficUnicastLocatorList;
  ports.metatraffic = meta.empty() && wire.builtin.metatrafficMulticastLocatorList.empty();
  for (const auto& locator : meta) {
    if (locator.kind == LOCATOR_KIND_SHM && locator.port == 0) ports.metatraffic = true;
  }
  return std::make_pair(ports, range > 0 ? static_cast<int>(range) : kDefaultMaxIds);
}

std::string port_list(const std::vector<std::uint32_t>& ports) {
  std::string out;
  for (const std::uint32_t p : ports) out += (out.empty() ? "" : ", ") + std::to_string(p);
  return out;
}

}  // namespace

ShmIdAssignment assign_shm_participant_id(DomainParticipantQos& qos, int domain, ShmChoiceLock& lock,
                                          const std::string& shm_dir) {
  ShmIdAssignment result;
  const auto plan = shm_listen_ports(qos);
  if (!plan) return result;
  const auto& [ports, max_ids] = *plan;
  const bool locked = lock.acquire(shm_dir, domain);
  std::vector<std::uint32_t> all;
  for (int id = 0; id < max_ids; ++id) {
    for (const std::uint32_t p : ports.of(domain, id)) all.push_back(p);
  }
  const auto states = read_shm_ports(all, shm_dir);
  const auto safe = [&](std::uint32_t p) {
    const auto it = states.find(p);
    return it == states.end() || shm_port_safe_to_listen(it->second);
  };
  const ShmIdChoice choice = choose_participant_id(ports, domain, max_ids, ids_in_this_process(), safe);
  std::vector<std::uint32_t> stale;  // passed over for a stale segment, not merely because a live reader has it
  for (const std::uint32_t p : choice.passed_over) {
    const auto it = states.find(p);
    if (it != states.end() && !it->second.reader_alive) stale.push_back(p);
  }
  if (choice.participant_id < 0) {
    result.warning = true;
    result.note = "no shared-memory port of participant ids 0.." + std::to_string(max_ids - 1) +
                  " is safe to listen on (stale segments of ports " + port_list(stale) +
                  " are still mapped by live processes); Fast DDS chooses, and a peer may not reach this process "
                  "over shared memory";
    return result;
  }
  qos.wire_protocol().participant_id = choice.participant_id;
  result.participant_id = choice.participant_id;
  result.ports = ports.of(domain, choice.participant_id);
  if (!stale.empty()) {
    result.note = "DDS participant id " + std::to_string(choice.participant_id) + " (shared-memory port " +
                  port_list(result.ports) + "): passed over port(s) " + port_list(stale) +
                  ": a live process still has the old segment of a killed reader open there";
  }
  if (!locked) {
    result.warning = true;
    result.note += std::string(result.note.empty() ? "" : "; ") + "could not take " + shm_dir +
                   "/causal_twin_ids_d" + std::to_string(domain) + ".lock within 10 s: chose without it";
  }
  return result;
}

bool listens_on_shm_port(std::uint32_t port, const std::string& shm_dir) {
  struct stat lock {};
  if (::stat((port_file(shm_dir, port) + "_el").c_str(), &lock) != 0) return false;
  std::ifstream locks("/proc/locks");
  const std::string self = std::to_string(::getpid());
  for (std::string line; std::getline(locks, line);) {
    // "1: FLOCK  ADVISORY  WRITE 4242 00:1a:5678 0 EOF"
    std::istringstream in(line);
    std::string n, kind, mode, access, pid, where;
    if (!(in >> n >> kind >> mode >> access >> pid >> where) || kind != "FLOCK" || pid != self) continue;
    const auto first = where.find(':');
    const auto second = where.rfind(':');
    if (first == std::string::npos || second == first) continue;
    const unsigned long maj = std::strtoul(where.substr(0, first).c_str(), nullptr, 16);
    const unsigned long min = std::strtoul(where.substr(first + 1, second - first - 1).c_str(), nullptr, 16);
    const unsigned long long inode = std::strtoull(where.substr(second + 1).c_str(), nullptr, 10);
    if (maj == major(lock.st_dev) && min == minor(lock.st_dev) && inode == lock.st_ino) return true;
  }
  return false;
}

bool shm_port_choice_enabled() {
  const char* value = std::getenv("CAUSAL_TWIN_SHM_PORT_CHOICE");
  return value != nullptr && std::string(value) == "1";
}

eprosima::fastdds::dds::DomainParticipant* create_participant_on_safe_shm_port(
    int domain, DomainParticipantQos qos, eprosima::fastdds::dds::DomainParticipantListener* listener,
    const eprosima::fastdds::dds::StatusMask& mask) {
  ShmChoiceLock lock;
  ShmIdAssignment shm;
  if (shm_port_choice_enabled()) shm = assign_shm_participant_id(qos, domain, lock);
  if (shm.warning) {
    spdlog::warn("{}", shm.note);
  } else if (!shm.note.empty()) {
    spdlog::info("{}", shm.note);
  }
  auto* participant = eprosima::fastdds::dds::DomainParticipantFactory::get_instance()->create_participant(
      static_cast<eprosima::fastdds::dds::DomainId_t>(domain), qos, listener, mask);
  lock.release();
  if (participant == nullptr) return nullptr;
  for (const std::uint32_t port : shm.ports) {
    if (!listens_on_shm_port(port)) {
      spdlog::warn("DDS participant id {} does not listen on shared-memory port {} it was given (another process "
                   "took it at the same moment): Fast DDS moved it on, perhaps onto a port a peer holds stale",
                   shm.participant_id, port);
    }
  }
  return participant;
}

}  // namespace causal::dds
