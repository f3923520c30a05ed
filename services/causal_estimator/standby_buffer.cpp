#include "standby_buffer.hpp"

namespace causal::estimator {

void StandbyBuffer::retain(const std::string& asset_group, std::vector<Item> items) {
  auto& q = retained_[asset_group];
  for (auto& item : items) q.push_back(std::move(item));
  while (q.size() > max_items_) {
    q.pop_front();
    ++discarded_;
  }
}

void StandbyBuffer::primary_published(const std::string& asset_group, std::uint64_t snapshot_index) {
  auto [it, created] = published_.try_emplace(asset_group, snapshot_index);
  if (!created && snapshot_index > it->second) it->second = snapshot_index;
}

std::vector<StandbyBuffer::Item> StandbyBuffer::take_over(std::uint64_t margin) {
  std::vector<Item> out;
  for (auto& [group, q] : retained_) {
    const auto p = published_.find(group);
    const std::uint64_t from = p == published_.end() ? 0 : (p->second > margin ? p->second - margin : 0);
    for (auto& item : q) {
      if (item.index >= from) out.push_back(std::move(item));
    }
  }
  retained_.clear();
  return out;
}

}  // namespace causal::estimator
