#include "reception_ledger.hpp"

#include <algorithm>
#include <set>

namespace causal::recorder {

void ReceptionLedger::note(const std::string& topic, const std::string& participant, const std::string& writer,
                           std::int64_t reception_ns) {
  auto [it, inserted] = last_.try_emplace(Key{topic, participant, writer}, reception_ns);
  if (!inserted) it->second = std::max(it->second, reception_ns);
}

std::vector<SilentWriter> ReceptionLedger::silent_after(std::int64_t stop_began_ns, std::int64_t active_window_ns,
                                                        std::int64_t heard_after_ns) const {
  std::set<std::string> unreachable;  // participants with a writer that was publishing and never came back
  for (const auto& [key, last] : last_) {
    if (last >= stop_began_ns - active_window_ns && last < heard_after_ns) unreachable.insert(key.participant);
  }
  std::vector<SilentWriter> silent;
  for (const auto& [key, last] : last_) {
    if (last < heard_after_ns && unreachable.count(key.participant) > 0) {
      silent.push_back({key.topic, key.participant, key.writer, last});
    }
  }
  return silent;
}

std::size_t ReceptionLedger::heard_after(std::int64_t heard_after_ns) const {
  return static_cast<std::size_t>(
      std::count_if(last_.begin(), last_.end(), [&](const auto& entry) { return entry.second >= heard_after_ns; }));
}

}  // namespace causal::recorder
