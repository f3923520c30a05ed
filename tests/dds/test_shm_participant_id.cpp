// The participant id on shared memory (causal/dds/shm_participant_id.hpp): which ports are safe to listen on,
// read from real files, locks and this process's own mappings in a private folder, and which id that gives.
#include "causal/dds/shm_participant_id.hpp"

#include <gtest/gtest.h>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using causal::dds::ShmListenPorts;
using causal::dds::ShmPortState;
using causal::dds::shm_port_safe_to_listen;

TEST(ShmPortSafety, OnlyPortsWithoutAStaleMappingAreSafe) {
  ShmPortState untouched;
  EXPECT_TRUE(shm_port_safe_to_listen(untouched));
  ShmPortState live;
  live.reader_alive = true;
  live.segment = 7;
  live.mapped = {7};
  EXPECT_FALSE(shm_port_safe_to_listen(live));
  ShmPortState dead_mapped;  // the stall: a writer still has the dead reader's segment open
  dead_mapped.reader_dead = true;
  dead_mapped.segment = 7;
  dead_mapped.mapped = {7};
  EXPECT_FALSE(shm_port_safe_to_listen(dead_mapped));
  ShmPortState dead_unmapped;  // replaced on open, nobody left behind
  dead_unmapped.reader_dead = true;
  dead_unmapped.segment = 7;
  EXPECT_TRUE(shm_port_safe_to_listen(dead_unmapped));
  ShmPortState left_cleanly;  // its reader exited cleanly; writers keep the segment, the next reader reads it
  left_cleanly.segment = 7;
  left_cleanly.mapped = {7};
  EXPECT_TRUE(shm_port_safe_to_listen(left_cleanly));
  ShmPortState removed_mapped;  // removed (fastdds shm clean) while a writer had it open
  removed_mapped.mapped = {7};
  EXPECT_FALSE(shm_port_safe_to_listen(removed_mapped));
  ShmPortState replaced_mapped;  // replaced while a writer had the old one open
  replaced_mapped.segment = 8;
  replaced_mapped.mapped = {7, 8};
  EXPECT_FALSE(shm_port_safe_to_listen(replaced_mapped));
}

TEST(ShmParticipantId, LowestIdWhosePortsAreAllSafe) {
  ShmListenPorts ports;  // Fast DDS's defaults: user traffic on 7400 + 250 d + 11 + 2 id
  EXPECT_EQ(ports.of(3, 2), (std::vector<std::uint32_t>{7400 + 750 + 11 + 4}));
  ports.metatraffic = true;
  EXPECT_EQ(ports.of(3, 2), (std::vector<std::uint32_t>{7400 + 750 + 10 + 4, 7400 + 750 + 11 + 4}));
  ports.metatraffic = false;
  const auto unsafe = [](std::vector<std::uint32_t> bad) {
    return [bad](std::uint32_t p) { return std::find(bad.begin(), bad.end(), p) == bad.end(); };
  };
  // Domain 0: id 0 -> 7411, id 1 -> 7413, id 2 -> 7415.
  auto c = causal::dds::choose_participant_id(ports, 0, 32, {}, unsafe({7411, 7413}));
  EXPECT_EQ(c.participant_id, 2);
  EXPECT_EQ(c.passed_over, (std::vector<std::uint32_t>{7411, 7413}));
  c = causal::dds::choose_participant_id(ports, 0, 32, {0, 2}, unsafe({7413}));
  EXPECT_EQ(c.participant_id, 3);  // 0 and 2 belong to this process, 1 is unsafe
  c = causal::dds::choose_participant_id(ports, 0, 3, {}, unsafe({7411, 7413, 7415}));
  EXPECT_EQ(c.participant_id, -1);
  EXPECT_EQ(c.passed_over.size(), 3u);
  ports.metatraffic = true;  // an id needs both of its ports
  c = causal::dds::choose_participant_id(ports, 0, 32, {}, unsafe({7410}));
  EXPECT_EQ(c.participant_id, 1);
  // Domain 232 (metatraffic 65410 + 2 id, user 65411 + 2 id): ids past port 65535 are no candidates.
  c = causal::dds::choose_participant_id(ports, 232, 100, {}, unsafe({}));
  EXPECT_EQ(c.participant_id, 0);
  // Ids 61 and 62 have ports 65532..65535; id 63 would have 65536.
  c = causal::dds::choose_participant_id(ports, 232, 100, {}, [](std::uint32_t p) { return p > 65530; });
  EXPECT_EQ(c.participant_id, 61);
  c = causal::dds::choose_participant_id(ports, 232, 100, {}, [](std::uint32_t p) { return p > 65535; });
  EXPECT_EQ(c.participant_id, -1);
}

namespace {

// A private folder standing for /dev/shm, with files named as Fast DDS names them.
class ShmFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/causal_shm_id_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    for (auto& [addr, size] : maps_) munmap(addr, size);
    for (int fd : fds_) close(fd);
    fs::remove_all(dir_);
  }
  std::string path(std::uint32_t port, const std::string& suffix = "") const {
    return dir_ + "/fastrtps_port" + std::to_string(port) + suffix;
  }
  void touch(const std::string& p) {
    const int fd = open(p.c_str(), O_RDWR | O_CREAT, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(ftruncate(fd, 4096), 0);
    close(fd);
  }
  void lock(const std::string& p) {  // held until TearDown, as a live reader holds it
    const int fd = open(p.c_str(), O_RDONLY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(flock(fd, LOCK_EX | LOCK_NB), 0);
    fds_.push_back(fd);
  }
  void map(const std::string& p) {  // as a writer maps a reader's port
    const int fd = open(p.c_str(), O_RDWR);
    ASSERT_GE(fd, 0);
    void* addr = mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    close(fd);
    ASSERT_NE(addr, MAP_FAILED);
    maps_.emplace_back(addr, 4096);
  }
  std::string dir_;
  std::vector<int> fds_;
  std::vector<std::pair<void*, std::size_t>> maps_;
};

}  // namespace

TEST_F(ShmFolder, ReadsLocksSegmentsAndLiveMappings) {
  touch(path(7001));  // a live reader
  touch(path(7001, "_el"));
  lock(path(7001, "_el"));
  touch(path(7003));  // a dead reader whose segment a writer (this process) still maps
  touch(path(7003, "_el"));
  map(path(7003));
  touch(path(7005));  // a dead reader nobody maps
  touch(path(7005, "_el"));
  touch(path(7007));  // mapped, then removed and created again
  map(path(7007));
  fs::remove(path(7007));
  touch(path(7007));
  touch(path(7009));  // left cleanly, mapped by a writer: the current segment
  map(path(7009));
  touch(path(7013));  // mapped and removed
  map(path(7013));
  fs::remove(path(7013));
  const auto states = causal::dds::read_shm_ports({7001, 7003, 7005, 7007, 7009, 7011, 7013}, dir_);
  ASSERT_EQ(states.size(), 7u);
  EXPECT_TRUE(states.at(7001).reader_alive);
  EXPECT_FALSE(states.at(7001).reader_dead);
  EXPECT_TRUE(states.at(7003).reader_dead);
  EXPECT_EQ(states.at(7003).mapped.size(), 1u);
  EXPECT_EQ(states.at(7003).mapped.count(*states.at(7003).segment), 1u);
  EXPECT_TRUE(states.at(7005).reader_dead);
  EXPECT_TRUE(states.at(7005).mapped.empty());
  EXPECT_EQ(states.at(7007).mapped.size(), 1u);
  EXPECT_EQ(states.at(7007).mapped.count(*states.at(7007).segment), 0u);
  EXPECT_FALSE(states.at(7011).segment.has_value());
  EXPECT_FALSE(states.at(7013).segment.has_value());
  EXPECT_EQ(states.at(7013).mapped.size(), 1u);
  std::vector<std::uint32_t> safe;
  for (const auto& [port, state] : states) {
    if (shm_port_safe_to_listen(state)) safe.push_back(port);
  }
  EXPECT_EQ(safe, (std::vector<std::uint32_t>{7005, 7009, 7011}));
  // The lock check after creation: this process holds 7001's reader lock, not 7005's.
  EXPECT_TRUE(causal::dds::listens_on_shm_port(7001, dir_));
  EXPECT_FALSE(causal::dds::listens_on_shm_port(7005, dir_));
  EXPECT_FALSE(causal::dds::listens_on_shm_port(7011, dir_));
}

TEST_F(ShmFolder, AssignsAnIdOnlyWithSharedMemory) {
  using eprosima::fastdds::dds::DomainParticipantQos;
  using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
  using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
  const int domain = 7;  // user ports 9161 + 2 id
  auto udp = std::make_shared<UDPv4TransportDescriptor>();
  udp->maxInitialPeersRange = 32;
  udp->interfaceWhiteList.emplace_back("127.0.0.1");

  DomainParticipantQos udp_only;  // localhost-udp.xml: nothing changes
  udp_only.transport().use_builtin_transports = false;
  udp_only.transport().user_transports.push_back(udp);
  causal::dds::ShmChoiceLock choice_lock;
  auto a = causal::dds::assign_shm_participant_id(udp_only, domain, choice_lock, dir_);
  EXPECT_EQ(a.participant_id, -1);
  EXPECT_EQ(udp_only.wire_protocol().participant_id, -1);
  EXPECT_FALSE(fs::exists(dir_ + "/causal_twin_ids_d7.lock"));

  DomainParticipantQos shm;  // localhost.xml
  shm.transport().use_builtin_transports = false;
  shm.transport().user_transports.push_back(std::make_shared<SharedMemTransportDescriptor>());
  shm.transport().user_transports.push_back(udp);
  shm.wire_protocol().builtin.metatrafficUnicastLocatorList.push_back(eprosima::fastrtps::rtps::Locator_t(0));
  touch(path(9161));  // id 0: a live reader
  touch(path(9161, "_el"));
  lock(path(9161, "_el"));
  touch(path(9163));  // id 1: a dead reader's segment still mapped
  touch(path(9163, "_el"));
  map(path(9163));
  DomainParticipantQos first = shm;
  a = causal::dds::assign_shm_participant_id(first, domain, choice_lock, dir_);
  EXPECT_EQ(a.participant_id, 2);
  EXPECT_EQ(first.wire_protocol().participant_id, 2);
  EXPECT_EQ(a.ports, (std::vector<std::uint32_t>{9165}));
  EXPECT_NE(a.note.find("passed over port(s) 9163"), std::string::npos) << a.note;
  EXPECT_FALSE(a.warning);
  EXPECT_TRUE(fs::exists(dir_ + "/causal_twin_ids_d7.lock"));
  choice_lock.release();

  DomainParticipantQos fixed = shm;  // a profile that sets the id itself
  fixed.wire_protocol().participant_id = 5;
  a = causal::dds::assign_shm_participant_id(fixed, domain, choice_lock, dir_);
  EXPECT_EQ(a.participant_id, -1);
  EXPECT_EQ(fixed.wire_protocol().participant_id, 5);
}
