// A reader killed with SIGKILL while its shared-memory receive thread was busy, restarted at once, on the
// shared-memory profile (deploy/dds/localhost.xml): the live writer that fed it must reach the new process.
// Fast DDS 2.9.1 lets the restarted process take its predecessor's shared-memory port and replace the dead
// segment without telling the writer, which had the old one open and goes on writing into it for ever
// (docs/reliability.md "Shared memory and SIGKILL"); common/dds/src/shm_participant_id.cpp chooses the
// participant id so that the new process listens on a port nobody holds a stale segment of
// ($CAUSAL_TWIN_SHM_PORT_CHOICE=1, set here). Without it both restarts took the dead reader's port and received
// 0 of 50 frames (2 of 2 runs).
// The stall is made deterministic: shm-restart-peer's reader blocks in its data callback (on the transport's
// receive thread) before it is killed, the state the writer's port watchdog does not detect.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "process_runner.hpp"
#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::test::counts_in_last_line;
using causal::test::ServiceProcess;

namespace {

constexpr int kBatch = 50;  // frames per reader: below the writer profile's 64 per instance, no write blocks

std::string port_of(const ServiceProcess& p) {
  const std::string out = p.output();
  const auto at = out.find("shm_port=");
  if (at == std::string::npos) return "";
  return out.substr(at + 9, out.find('\n', at) - at - 9);
}

std::unique_ptr<ServiceProcess> peer(const fs::path& work, const std::string& tag, std::vector<std::string> args) {
  args.insert(args.begin(), SHM_RESTART_PEER_BIN);
  return std::make_unique<ServiceProcess>(tag, args, (work / (tag + ".log")).string());
}

// Starts the writer and a first reader that stalls in its data callback after `stall_after` frames, then kills
// that reader with SIGKILL; returns the dead reader's shared-memory port.
std::string kill_a_busy_reader(const fs::path& work, const std::string& domain, const std::string& tag,
                               std::unique_ptr<ServiceProcess>& writer) {
  if (!writer) writer = peer(work, "writer", {"writer", domain, std::to_string(kBatch), "60"});
  EXPECT_TRUE(writer->wait_for_output("shm_port=", std::chrono::seconds(20))) << writer->output();
  auto stalled = peer(work, tag, {"reader", domain, std::to_string(kBatch), "60", "10"});
  EXPECT_TRUE(stalled->wait_for_output("stalled after", std::chrono::seconds(30)))
      << stalled->output() << writer->output();
  const std::string port = port_of(*stalled);
  EXPECT_EQ(stalled->kill_hard(), 128 + 9);
  return port;
}

}  // namespace

TEST(ShmRestart, ReaderKilledWhileBusyGetsEveryFrameAfterRestart) {
  setenv("CAUSAL_TWIN_SHM_PORT_CHOICE", "1", 1);  // the peers inherit it
  const fs::path work = causal::test::fresh_work_dir("causal_shm_restart", "busy");
  const std::string domain = std::to_string(causal::test::private_domain_id(41));
  // The choice's host-wide lock file of this private domain outlives the peers: removed at the end, pass or fail.
  struct RemoveLock {
    fs::path path;
    ~RemoveLock() {
      std::error_code ec;
      fs::remove(path, ec);
    }
  } remove_lock{fs::path("/dev/shm") / ("causal_twin_ids_d" + domain + ".lock")};
  std::unique_ptr<ServiceProcess> writer;
  const std::string dead_port = kill_a_busy_reader(work, domain, "reader-1", writer);
  ASSERT_NE(dead_port, "");
  ASSERT_NE(dead_port, "none") << "the reader listens on no shared-memory port: is localhost.xml the SHM profile?";

  // Restarted at once, while the writer still has the dead reader matched (its lease is 5 s).
  auto restarted = peer(work, "reader-2", {"reader", domain, std::to_string(kBatch), "20"});
  const auto code = restarted->wait(std::chrono::seconds(40));
  ASSERT_TRUE(code.has_value()) << restarted->output();
  const std::string new_port = port_of(*restarted);
  EXPECT_NE(new_port, dead_port) << "the restarted reader took its dead predecessor's shared-memory port";
  EXPECT_EQ(*code, 0) << restarted->output() << writer->output();
  const auto counts = counts_in_last_line(restarted->output(), "shm-restart-peer reader:");
  EXPECT_EQ(counts.at("batch"), 2u) << restarted->output();
  EXPECT_EQ(counts.at("received"), static_cast<std::uint64_t>(kBatch)) << restarted->output() << writer->output();
  EXPECT_EQ(counts.at("duplicates"), 0u);
  EXPECT_EQ(counts.at("other_batches"), 0u);

  // Killed and restarted a second time: the first dead port is still held stale by the writer, the second too.
  const std::string second_dead = kill_a_busy_reader(work, domain, "reader-3", writer);
  auto again = peer(work, "reader-4", {"reader", domain, std::to_string(kBatch), "20"});
  const auto code2 = again->wait(std::chrono::seconds(40));
  ASSERT_TRUE(code2.has_value()) << again->output();
  EXPECT_NE(port_of(*again), dead_port);
  EXPECT_NE(port_of(*again), second_dead);
  EXPECT_EQ(*code2, 0) << again->output() << writer->output();
  const auto counts2 = counts_in_last_line(again->output(), "shm-restart-peer reader:");
  EXPECT_EQ(counts2.at("batch"), 4u) << again->output();
  EXPECT_EQ(counts2.at("received"), static_cast<std::uint64_t>(kBatch)) << again->output();
  writer->terminate();
}
