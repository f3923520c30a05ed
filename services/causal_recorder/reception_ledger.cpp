#include "reception_ledger.hpp"

#include <algorithm>
#include <optional>
#include <set>

namespace causal::recorder {

void ReceptionLedger::note(const std::string& topic, const std::string& participant, const std::string& writer,
                           std::uint64_t sequence_number, std::int64_t reception_ns) {
  Writer& w = writers_[Key{topic, participant, writer}];
  w.last_ns = std::max(w.last_ns, reception_ns);
  w.sequence_numbers.record(sequence_number);
  // Takes from several readers interleave, so a reception may be a little older than the segment's last one.
  if (w.segments.empty() || reception_ns >= w.segments.back().last_ns + kSegmentGapNs) {
    w.segments.push_back({reception_ns, reception_ns, sequence_number});
    if (w.segments.size() > kSegments) w.segments.pop_front();
    return;
  }
  Segment& seg = w.segments.back();
  seg.first_ns = std::min(seg.first_ns, reception_ns);
  seg.last_ns = std::max(seg.last_ns, reception_ns);
  seg.highest = std::max(seg.highest, sequence_number);
}

std::vector<SilentWriter> ReceptionLedger::silent_after(std::int64_t stop_began_ns, std::int64_t active_window_ns,
                                                        std::int64_t heard_after_ns) const {
  std::set<std::string> unreachable;  // participants with a writer that was publishing and never came back
  for (const auto& [key, w] : writers_) {
    if (w.last_ns >= stop_began_ns - active_window_ns && w.last_ns < heard_after_ns) {
      unreachable.insert(key.participant);
    }
  }
  std::vector<SilentWriter> silent;
  for (const auto& [key, w] : writers_) {
    if (w.last_ns < heard_after_ns && unreachable.count(key.participant) > 0) {
      silent.push_back({key.topic, key.participant, key.writer, w.last_ns});
    }
  }
  return silent;
}

std::size_t ReceptionLedger::heard_after(std::int64_t heard_after_ns) const {
  return static_cast<std::size_t>(
      std::count_if(writers_.begin(), writers_.end(), [&](const auto& entry) { return entry.second.last_ns >= heard_after_ns; }));
}

std::vector<MissedSamples> ReceptionLedger::missed_across(std::int64_t heard_after_ns) const {
  // The highest sequence number each writer had delivered before the stop, from the segments that ended before it
  // (a segment cannot span the stop: a stopped process receives nothing). Kept segments only.
  std::map<Key, std::uint64_t> before;
  std::set<std::string> connected;  // participants heard before the stop: the recorder was matched with them
  for (const auto& [key, w] : writers_) {
    for (const Segment& seg : w.segments) {
      if (seg.last_ns >= heard_after_ns) continue;
      before[key] = std::max(before[key], seg.highest);
      connected.insert(key.participant);
    }
  }
  std::vector<MissedSamples> missed;
  for (const auto& [key, w] : writers_) {
    if (w.last_ns < heard_after_ns) continue;  // not heard again: silent_after's case
    std::uint64_t from = 0;                    // sequence numbers above this one count
    if (const auto it = before.find(key); it != before.end()) {
      from = it->second;
    } else if (connected.count(key.participant) == 0) {
      continue;  // a participant first heard after the stop: a late joiner's history, not samples it missed
    }
    // else: a writer of a connected participant with nothing delivered before the stop (alarm-recommender's
    // prognoses start with the first degradation alarm): everything from its first sample on counts.
    MissedSamples m{key.topic, key.participant, key.writer, 0, {}};
    auto add = [&m](std::uint64_t first, std::uint64_t last) {
      m.count += last - first + 1;
      m.sequence_numbers.push_back({first, last});
    };
    const std::uint64_t lowest = w.sequence_numbers.lowest().value_or(1);
    if (lowest > from + 1) add(from + 1, lowest - 1);  // RTPS sequence numbers start at 1
    for (const dds::IndexRange& r : w.sequence_numbers.missing()) {
      if (r.last > from) add(std::max(r.first, from + 1), r.last);
    }
    if (m.count > 0) missed.push_back(std::move(m));
  }
  return missed;
}

}  // namespace causal::recorder
