// Which indices of one message stream (snapshot or sample indices) a consumer already has, so a re-sent
// or replayed message is recognised as a duplicate, and which ones it never got (the gaps).
// Standard library only: consumers decide what to log.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace causal::dds {

// Closed range of indices [first, last].
struct IndexRange {
  std::uint64_t first = 0;
  std::uint64_t last = 0;
  bool operator==(const IndexRange& o) const { return first == o.first && last == o.last; }
};

// A set of indices stored as disjoint runs of consecutive indices: memory grows with the number of
// gaps, not with the number of indices, so a week of snapshots in order costs one entry.
class IndexLedger {
 public:
  // True when the index is new (and is now recorded), false when it was recorded before.
  bool record(std::uint64_t index);
  bool contains(std::uint64_t index) const;

  std::uint64_t count() const { return count_; }  // distinct indices recorded
  std::optional<std::uint64_t> lowest() const;
  std::optional<std::uint64_t> highest() const;
  // The indices between the lowest and the highest recorded one that were never recorded, ascending.
  std::vector<IndexRange> missing() const;
  std::uint64_t missing_count() const;

 private:
  std::map<std::uint64_t, std::uint64_t> runs_;  // first -> last of each run, disjoint and not adjacent
  std::uint64_t count_ = 0;
};

// "120..131, 140, 200..210" (at most max_shown ranges, then "and N more"); "" when there are none.
std::string describe_ranges(const std::vector<IndexRange>& ranges, std::size_t max_shown = 10);

}  // namespace causal::dds
