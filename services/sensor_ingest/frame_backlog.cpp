#include "frame_backlog.hpp"

namespace causal::ingest {

void FrameBacklog::keep(const causal_twin::VibrationFrame& frame) {
  if (capacity_ == 0) return;
  auto& q = frames_[frame.asset_group()];
  q.push_back(frame);
  while (q.size() > capacity_) {
    q.pop_front();
    ++evicted_;
  }
}

std::vector<const causal_twin::VibrationFrame*> FrameBacklog::after(const std::string& group,
                                                                    std::optional<std::uint64_t> after_snapshot) const {
  std::vector<const causal_twin::VibrationFrame*> out;
  const auto it = frames_.find(group);
  if (it == frames_.end()) return out;
  for (const auto& f : it->second) {
    if (!after_snapshot || f.snapshot_index() > *after_snapshot) out.push_back(&f);
  }
  return out;
}

std::optional<std::uint64_t> FrameBacklog::oldest_snapshot(const std::string& group) const {
  const auto it = frames_.find(group);
  if (it == frames_.end() || it->second.empty()) return std::nullopt;
  return it->second.front().snapshot_index();
}

std::vector<std::string> FrameBacklog::groups() const {
  std::vector<std::string> out;
  for (const auto& [g, q] : frames_) out.push_back(g);
  return out;
}

}  // namespace causal::ingest
