// Who stopped reaching this recorder across a suspension (SIGSTOP, a VM pause). After a stop longer than the
// participant lease the peers drop the recorder; when it runs again they re-discover it and a TRANSIENT_LOCAL
// writer that is still there re-sends its history ring to the re-matched reader. So a writer that was publishing
// when the stop began and is never heard after the resume either left meanwhile or cannot reach the recorder any
// more (Fast DDS 2.9 over shared memory may never send again to a port that stalled): what it published from the
// stop on is missing, and no later index shows the gap. One writer is enough: other writers that do reach the
// recorder again (say alarm-recommender's history) must not hide it. The stall is per sending participant, so the
// other writers of that participant that were not heard again are named with it, however long they had been quiet
// before the stop (an alarm writer publishes only now and then).
//
// A writer that does reach the recorder again re-sends only its history ring (the last 64 statuses per group,
// 8 updates per alarm, ...): what it published during the stop beyond that never arrives, and statuses and
// prognoses carry no index to show it. Its RTPS sequence numbers do: one per sample written, so the numbers
// above the highest one received before the stop that never arrived are exactly the samples missed.
#pragma once

#include "causal/dds/index_ledger.hpp"

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace causal::recorder {

struct SilentWriter {
  std::string topic;
  std::string participant;             // its GUID prefix, as text
  std::string writer;                  // its entity id, as text
  std::int64_t last_reception_ns = 0;  // system clock, DDS reception timestamp
};

// Samples of one writer published while the recorder was stopped and never received.
struct MissedSamples {
  std::string topic, participant, writer;
  std::uint64_t count = 0;
  std::vector<dds::IndexRange> sequence_numbers;  // ascending
};

class ReceptionLedger {
 public:
  // A sample of `topic` from `writer` arrived at reception_ns (system clock). Only topics whose reader is
  // TRANSIENT_LOCAL belong here: a volatile writer that is still there sends nothing after a re-match.
  // sequence_number: the sample's RTPS sequence number (SampleInfo::sample_identity).
  void note(const std::string& topic, const std::string& participant, const std::string& writer,
            std::uint64_t sequence_number, std::int64_t reception_ns);

  // Writers heard within `active_window_ns` before the stop began (stop_began_ns) and not at or after
  // heard_after_ns (the resume minus a margin: samples that arrived before the stop and were taken just after it
  // are not news from after it), and the other writers of their participants not heard after it either. Ordered by
  // topic, participant, writer.
  std::vector<SilentWriter> silent_after(std::int64_t stop_began_ns, std::int64_t active_window_ns,
                                         std::int64_t heard_after_ns) const;

  // Writers heard at or after heard_after_ns (those that reached the recorder again).
  std::size_t heard_after(std::int64_t heard_after_ns) const;

  // Per writer heard at or after heard_after_ns: the sequence numbers above the highest one received before it
  // that never arrived, up to the highest received at all. A writer first heard after it counts from its first
  // sample when its participant was heard before (the recorder was matched with it all along), and not at all
  // otherwise (a late joiner's history). Writers that missed nothing are left out. Ordered by topic, participant,
  // writer.
  std::vector<MissedSamples> missed_across(std::int64_t heard_after_ns) const;

  bool empty() const { return writers_.empty(); }

 private:
  struct Key {
    std::string topic, participant, writer;
    bool operator<(const Key& o) const {
      return std::tie(topic, participant, writer) < std::tie(o.topic, o.participant, o.writer);
    }
  };
  // Receptions without a pause of kSegmentGapNs or more between them: where a stop falls is a segment boundary
  // (a stopped process receives nothing), so the highest sequence number before it is the highest of the segments
  // that ended before it. The last kSegments are kept (a writer that publishes once a minute makes one per sample).
  struct Segment {
    std::int64_t first_ns = 0, last_ns = 0;
    std::uint64_t highest = 0;
  };
  static constexpr std::int64_t kSegmentGapNs = 1'000'000'000;
  static constexpr std::size_t kSegments = 64;
  struct Writer {
    std::int64_t last_ns = 0;  // latest reception
    dds::IndexLedger sequence_numbers;
    std::deque<Segment> segments;  // in order of reception
  };
  std::map<Key, Writer> writers_;
};

}  // namespace causal::recorder
