#include "causal/dds/index_ledger.hpp"

#include <iterator>

namespace causal::dds {

bool IndexLedger::record(std::uint64_t index) {
  // The run starting after index, and the one before it (the only one that can contain index).
  auto next = runs_.upper_bound(index);
  if (next != runs_.begin()) {
    auto prev = std::prev(next);
    if (index <= prev->second) return false;
    if (prev->second + 1 == index) {
      prev->second = index;  // extends the previous run; may now touch the next one
      if (next != runs_.end() && next->first == index + 1) {
        prev->second = next->second;
        runs_.erase(next);
      }
      ++count_;
      return true;
    }
  }
  if (next != runs_.end() && next->first == index + 1) {
    const std::uint64_t last = next->second;  // extends the next run downwards: re-key it
    runs_.erase(next);
    runs_.emplace(index, last);
  } else {
    runs_.emplace(index, index);
  }
  ++count_;
  return true;
}

bool IndexLedger::contains(std::uint64_t index) const {
  auto next = runs_.upper_bound(index);
  if (next == runs_.begin()) return false;
  return index <= std::prev(next)->second;
}

std::optional<std::uint64_t> IndexLedger::lowest() const {
  if (runs_.empty()) return std::nullopt;
  return runs_.begin()->first;
}

std::optional<std::uint64_t> IndexLedger::highest() const {
  if (runs_.empty()) return std::nullopt;
  return runs_.rbegin()->second;
}

std::vector<IndexRange> IndexLedger::missing() const {
  std::vector<IndexRange> gaps;
  for (auto it = runs_.begin(); it != runs_.end(); ++it) {
    auto next = std::next(it);
    if (next == runs_.end()) break;
    gaps.push_back({it->second + 1, next->first - 1});  // runs are never adjacent: the gap is not empty
  }
  return gaps;
}

std::uint64_t IndexLedger::missing_count() const {
  if (runs_.empty()) return 0;
  return runs_.rbegin()->second - runs_.begin()->first + 1 - count_;
}

std::string describe_ranges(const std::vector<IndexRange>& ranges, std::size_t max_shown) {
  std::string s;
  const std::size_t shown = ranges.size() < max_shown ? ranges.size() : max_shown;
  for (std::size_t i = 0; i < shown; ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(ranges[i].first);
    if (ranges[i].last != ranges[i].first) s += ".." + std::to_string(ranges[i].last);
  }
  if (ranges.size() > shown) s += " and " + std::to_string(ranges.size() - shown) + " more";
  return s;
}

}  // namespace causal::dds
