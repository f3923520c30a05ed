// causal-estimator: the condition-level output of an asset group that the readers have not acknowledged yet,
// kept in the group's checkpoint (EstimatorStateStore's resend list) so a restarted estimator sends it again.
//
// The checkpoint is written before a snapshot's output is queued, and the outbound queue may hold the output of
// many snapshots (a calibration window's replay, writes waiting on a reader that stopped acknowledging until its
// lease expires). Keeping only the last snapshot's output lost everything queued before it when the process was
// killed. Here every message stays listed from the snapshot that made it until (1) the writer accepted it (the
// outbound queue's write returned Ok) and (2) afterwards every matched reliable reader acknowledged everything
// the writers hold (DataWriter::wait_for_acknowledgments with no wait). Consumers drop what they already have
// by index, so sending a message twice is harmless; not sending it is a gap.
//
// Bound: the output of kMaxSnapshots snapshots, the same as sensor-ingest's --backlog default (600 frames, one
// snapshot each on a live block source): with more unacknowledged than that the source cannot resend the input
// either. Beyond it the oldest snapshot's messages leave the list (still queued; lost only if the process dies
// before they are delivered, then counted by the readers as lost input) and are counted in dropped().
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace causal::estimator {

class UnackedOutput {
 public:
  static constexpr std::size_t kMaxSnapshots = 600;
  using Flag = std::shared_ptr<std::atomic<bool>>;

  // Starts the output of one snapshot (or of the messages restored from a checkpoint).
  void begin_snapshot();
  // Lists one message (its wire form, tagged as the checkpoint keeps it); the returned flag is set by the write
  // once the writer accepted the message.
  Flag add(std::string bytes);
  // Forgets the messages written so far when `all_acked` (asked after looking at the flags) says every matched
  // reader acknowledged every sample the writers hold.
  void settle(const std::function<bool()>& all_acked);
  // The messages still listed, oldest first: the checkpoint's resend list.
  std::vector<std::string> list() const;
  std::size_t messages() const;
  std::uint64_t dropped() const { return dropped_; }

 private:
  struct Message {
    std::string bytes;
    Flag written;
  };
  std::deque<std::vector<Message>> snapshots_;
  std::uint64_t dropped_ = 0;
};

}  // namespace causal::estimator
