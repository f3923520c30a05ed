#include "unacked_output.hpp"

namespace causal::estimator {

void UnackedOutput::begin_snapshot() {
  if (!snapshots_.empty() && snapshots_.back().empty()) return;  // the previous one made no output: reuse it
  snapshots_.emplace_back();
  while (snapshots_.size() > kMaxSnapshots) {
    dropped_ += snapshots_.front().size();
    snapshots_.pop_front();
  }
}

UnackedOutput::Flag UnackedOutput::add(std::string bytes) {
  if (snapshots_.empty()) snapshots_.emplace_back();
  auto flag = std::make_shared<std::atomic<bool>>(false);
  snapshots_.back().push_back({std::move(bytes), flag});
  return flag;
}

void UnackedOutput::settle(const std::function<bool()>& all_acked) {
  // Which messages were written is read BEFORE asking: a message written after the question may not be covered.
  std::vector<std::vector<bool>> written;
  bool any = false;
  for (const auto& s : snapshots_) {
    written.emplace_back();
    for (const auto& m : s) {
      written.back().push_back(m.written->load());
      any = any || written.back().back();
    }
  }
  if (!any || !all_acked()) return;
  std::deque<std::vector<Message>> kept;
  for (std::size_t i = 0; i < snapshots_.size(); ++i) {
    std::vector<Message> left;
    for (std::size_t j = 0; j < snapshots_[i].size(); ++j) {
      if (!written[i][j]) left.push_back(std::move(snapshots_[i][j]));
    }
    if (!left.empty() || i + 1 == snapshots_.size()) kept.push_back(std::move(left));
  }
  snapshots_ = std::move(kept);
}

std::vector<std::string> UnackedOutput::list() const {
  std::vector<std::string> out;
  for (const auto& s : snapshots_) {
    for (const auto& m : s) out.push_back(m.bytes);
  }
  return out;
}

std::size_t UnackedOutput::messages() const {
  std::size_t n = 0;
  for (const auto& s : snapshots_) n += s.size();
  return n;
}

}  // namespace causal::estimator
