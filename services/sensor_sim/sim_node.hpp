// sensor-sim's DDS node: N simulated asset groups published round-robin on the vibration-frame topic.
// run() publishes until --frames-per-group, --max-runtime or stop() (from the signal thread), whichever comes
// first. Exit codes: 0 done, 3 no readers in time, 4 frames lost (a write failed or timed out).
#pragma once

#include "sim_options.hpp"
#include "svar_generator.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <vector>

namespace causal::sim {

class SimNode {
 public:
  explicit SimNode(SimOptions options);
  int run();
  void stop();

 private:
  struct Group {
    SvarGenerator generator;
    dds::FrameHeader header;  // sequence and first_sample_index advance with every frame
    std::uint64_t sent = 0;
  };
  using Clock = std::chrono::steady_clock;

  // Sleeps until `due` (or the runtime deadline). False if stopped meanwhile.
  bool sleep_until(Clock::time_point due);
  // Publishes frame `round` of every group; false once stopped.
  bool publish_round(std::uint64_t round, Eigen::MatrixXd& block);
  void print_summary() const;

  SimOptions options_;
  dds::Participant participant_;
  dds::TypedWriter<causal_twin::VibrationFramePubSubType> frames_;
  std::vector<Group> groups_;
  causal_twin::VibrationFrame frame_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  Clock::time_point started_;
  Clock::time_point origin_;  // when publishing started (pacing)
  Clock::time_point deadline_ = Clock::time_point::max();  // --max-runtime
  std::uint64_t sent_ = 0, lost_ = 0;
};

}  // namespace causal::sim
