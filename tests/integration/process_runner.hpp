// Starts a real service process for an integration test, captures its output to a file, waits for it with
// a bound, and ends it by pid (SIGTERM, then SIGKILL after a grace period) if it is still running. Only
// processes started here are ever signalled.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

namespace causal::test {

class ServiceProcess {
 public:
  ServiceProcess(std::string name, std::vector<std::string> argv, std::string log_path);
  ~ServiceProcess();  // terminate() if still running
  ServiceProcess(const ServiceProcess&) = delete;
  ServiceProcess& operator=(const ServiceProcess&) = delete;

  // Waits up to `timeout` for the process to exit; returns its exit code (128 + signal if killed), or
  // nullopt on timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  bool running();
  // SIGTERM, wait up to `grace`, then SIGKILL. Returns the exit code.
  int terminate(std::chrono::milliseconds grace = std::chrono::seconds(10));
  // SIGKILL at once, as a crash would end it (no signal handler, no clean-up). Returns the exit code.
  int kill_hard();
  std::string output() const;  // everything it printed so far
  // Waits up to `timeout` until its output holds `text` (`occurrences` times); false when it has not by then or
  // ended without it.
  bool wait_for_output(const std::string& text, std::chrono::milliseconds timeout, std::size_t occurrences = 1);
  const std::string& name() const { return name_; }
  pid_t pid() const { return pid_; }

 private:
  std::string name_;
  std::string log_path_;
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
};

// The key=value numbers of the last line of `output` that contains `marker` (a service's summary line, e.g.
// "sensor-ingest: received=7 published=5 ... malformed=1"); empty when there is no such line.
std::map<std::string, std::uint64_t> counts_in_last_line(const std::string& output, const std::string& marker);

// A private DDS domain id for this test process (100..199), so concurrent runs do not hear each other: claimed
// with a lock held until the process exits (/tmp/causal-test-domain-ID.lock).
int private_domain_id(int salt);

// Removes shared-memory files left by Fast DDS processes that are gone (`fastdds shm clean` only touches
// segments whose owners have exited). Returns false if the tool is missing.
bool clean_stale_shared_memory();

}  // namespace causal::test
