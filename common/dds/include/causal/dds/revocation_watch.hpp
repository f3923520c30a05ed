// Revocation without downtime. Fast DDS 2.9 reads the identity CA's revocation list
// once, when a participant is created (PKIDH::validate_local_identity), and never checks a peer it has
// authenticated again: a revoked sensor stays accepted by every running service. So every process watches the
// revocation list its participants loaded (DIR/identity_ca.crl, which make-pki.sh creates empty) and, when its
// content changes, restarts itself in place (run_service: a clean stop, checkpoints written, then exec of the
// same command line, same pid): its new participant loads the new list and refuses the revoked identity in the
// handshake. The services resume from their checkpoints (--state-dir) and the sources rewind to them, as after
// any restart. Within kRevocationPoll + the restart (measured in docs/security.md).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace causal::dds {

inline constexpr std::chrono::seconds kRevocationPoll{10};

class RevocationWatch {
 public:
  ~RevocationWatch() { stop(); }
  // Watches `crl_path` from now on (its present content, or its absence, is the baseline).
  void watch(const std::string& crl_path);
  // Polls every `interval` on a thread of its own; on_change(path) runs once, on that thread, at the first change.
  void start(std::chrono::milliseconds interval, std::function<void(const std::string&)> on_change);
  void stop();
  bool watching() const;

 private:
  void loop(std::chrono::milliseconds interval);
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, std::string> baseline_;  // path -> content ("" = absent)
  std::function<void(const std::string&)> on_change_;
  bool stopping_ = false;
  std::thread thread_;
};

// The one watch of this process (participants register their lists, run_service starts it).
RevocationWatch& process_revocation_watch();

// Replaces this process by a new run of the same executable with the same arguments (/proc/self/cmdline).
// Returns only when that fails (the reason is logged).
void exec_self();

}  // namespace causal::dds
