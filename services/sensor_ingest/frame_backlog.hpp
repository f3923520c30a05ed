// sensor-ingest's backlog: the last frames it published, per asset group, resent to an estimator that appears
// after a restart. A live source (MQTT, UDP, stdin) cannot rewind, and the frame topic is VOLATILE (qos.xml):
// what was published while no estimator read it reaches a restarted one only from here. Bounded per asset
// group (--backlog FRAMES); a restarted estimator that needs older frames than kept counts the gap itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "causal_twin.h"

namespace causal::ingest {

class FrameBacklog {
 public:
  explicit FrameBacklog(std::size_t frames_per_group) : capacity_(frames_per_group) {}
  bool enabled() const { return capacity_ > 0; }
  std::size_t capacity() const { return capacity_; }
  // Keeps a copy of a published frame; the group's oldest frame goes when the group holds `capacity` frames.
  void keep(const causal_twin::VibrationFrame& frame);
  // The frames of `group` from the first one of a snapshot after `after_snapshot` (every kept frame when none),
  // in publication order.
  std::vector<const causal_twin::VibrationFrame*> after(const std::string& group,
                                                        std::optional<std::uint64_t> after_snapshot) const;
  // The oldest snapshot index still kept for `group` (none when nothing is kept).
  std::optional<std::uint64_t> oldest_snapshot(const std::string& group) const;
  std::vector<std::string> groups() const;
  std::uint64_t evicted() const { return evicted_; }

 private:
  std::size_t capacity_;
  std::map<std::string, std::deque<causal_twin::VibrationFrame>> frames_;
  std::uint64_t evicted_ = 0;
};

}  // namespace causal::ingest
