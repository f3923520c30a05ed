// Per-frame stage timestamps of causal-estimator (--stage-trace FILE): where a frame's time goes between the
// source and the sample-level filter message leaving for the readers (docs/scale-and-benchmarks.md "Latency
// spikes"). Off by default; when on, one row per frame is kept in memory and written as CSV at exit:
//   group,sequence,due_ns,source_ns,received_ns,taken_ns,fed_ns,queued_ns,write_start_ns,write_end_ns,queue_depth
// All times are wall-clock ns (system_clock, the clock of first_sample_time_ns under sensor-sim
// --wall-clock-stamps and of DDS's source/reception timestamps), so the stages line up with the frame's due time:
//   source - due: the source's own delay; received - source: transport; taken - received: the event loop's wake-up;
//   fed - taken: the filters; queued - fed: output conversion, the checkpoint and the push (which includes the
//   write itself when it is written inline); write_start - queued: the outbound queue's wait (negative when the
//   message was written inline, OutboundQueue::write_or_push); write_end - write_start: the DDS write.
//   queue_depth: messages queued or in flight when the frame's output was pushed.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace causal::estimator {

class StageTrace {
 public:
  struct Frame {
    std::string group;
    std::uint64_t sequence = 0;
    std::int64_t due_ns = 0, source_ns = 0, received_ns = 0, taken_ns = 0, fed_ns = 0, queued_ns = 0;
    std::atomic<std::int64_t> write_start_ns{0}, write_end_ns{0};
    std::size_t queue_depth = 0;
  };

  explicit StageTrace(std::string path) : path_(std::move(path)) {}
  bool enabled() const { return !path_.empty(); }
  static std::int64_t now_ns();
  // Keeps a frame's row (its write times may still be filled in by the drain thread until write()).
  void keep(std::shared_ptr<Frame> frame);
  // Writes the CSV; returns "" or why it could not.
  std::string write() const;
  std::size_t rows() const;

 private:
  std::string path_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Frame>> frames_;
};

// "user_s=U sys_s=S frames=N cpu_per_frame_us=C": this process's user and system CPU so far (start-up included)
// and per frame processed.
std::string process_cpu_summary(std::uint64_t frames);

}  // namespace causal::estimator
