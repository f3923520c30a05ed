// Hot standby (causal-estimator --standby): a second estimator that receives the same input as the primary,
// runs the same filters (so its state is always current), but publishes nothing while a primary is alive. It
// keeps the condition-level output of its last snapshots here and follows what the primary published (on
// causal_twin/condition_vector). When the primary has been gone for longer than its lease, the standby takes
// over: it publishes its retained output from a little before the primary's last published snapshot (consumers
// drop what they already have, by index) and then goes on as the primary. Same input, same filters, same output:
// the readers see one continuous stream.
#pragma once

#include "causal/dds/outbound_queue.hpp"

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace causal::estimator {

class StandbyBuffer {
 public:
  struct Item {
    std::string stream;
    dds::OutboundQueue::Class cls;
    dds::OutboundQueue::WriteFn write;
    std::uint64_t index = 0;  // snapshot index the message refers to
  };

  // max_items: messages retained per asset group (the oldest go first).
  explicit StandbyBuffer(std::size_t max_items) : max_items_(max_items) {}

  void retain(const std::string& asset_group, std::vector<Item> items);
  void primary_published(const std::string& asset_group, std::uint64_t snapshot_index);
  // What to publish when taking over: per asset group, the retained messages whose index is at least the
  // primary's last published index minus `margin` (all of them when the primary published nothing), in order.
  // Empties the buffer.
  std::vector<Item> take_over(std::uint64_t margin);

  std::uint64_t discarded() const { return discarded_; }  // retained messages pushed out by newer ones

 private:
  std::size_t max_items_;
  std::map<std::string, std::deque<Item>> retained_;
  std::map<std::string, std::uint64_t> published_;
  std::uint64_t discarded_ = 0;
};

}  // namespace causal::estimator
