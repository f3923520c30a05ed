#include "reception_ledger.hpp"

#include <algorithm>

namespace causal::recorder {

void ReceptionLedger::note(const std::string& topic, const std::string& writer, std::int64_t reception_ns) {
  auto [it, inserted] = last_.try_emplace({topic, writer}, reception_ns);
  if (!inserted) it->second = std::max(it->second, reception_ns);
}

std::vector<SilentWriter> ReceptionLedger::silent_after(std::int64_t stop_began_ns, std::int64_t active_window_ns,
                                                        std::int64_t heard_after_ns) const {
  std::vector<SilentWriter> silent;
  for (const auto& [key, last] : last_) {
    const bool active_at_stop = last >= stop_began_ns - active_window_ns;
    if (active_at_stop && last < heard_after_ns) silent.push_back({key.first, key.second, last});
  }
  return silent;
}

std::size_t ReceptionLedger::heard_after(std::int64_t heard_after_ns) const {
  return static_cast<std::size_t>(
      std::count_if(last_.begin(), last_.end(), [&](const auto& entry) { return entry.second >= heard_after_ns; }));
}

}  // namespace causal::recorder
