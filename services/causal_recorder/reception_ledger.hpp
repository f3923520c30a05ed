// Who stopped reaching this recorder across a suspension (SIGSTOP, a VM pause). After a stop longer than the
// participant lease the peers drop the recorder; when it runs again they re-discover it and a TRANSIENT_LOCAL
// writer that is still there re-sends its history ring to the re-matched reader. So a writer that was publishing
// when the stop began and is never heard after the resume either left meanwhile or cannot reach the recorder any
// more (Fast DDS 2.9 over shared memory may never send again to a port that stalled): what it published from the
// stop on is missing, and no later index shows the gap. One writer is enough: other writers that do reach the
// recorder again (say alarm-recommender's history) must not hide it. The stall is per sending participant, so the
// other writers of that participant that were not heard again are named with it, however long they had been quiet
// before the stop (an alarm writer publishes only now and then).
#pragma once

#include <cstddef>
#include <cstdint>
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

class ReceptionLedger {
 public:
  // A sample of `topic` from `writer` arrived at reception_ns (system clock). Only topics whose reader is
  // TRANSIENT_LOCAL belong here: a volatile writer that is still there sends nothing after a re-match.
  void note(const std::string& topic, const std::string& participant, const std::string& writer,
            std::int64_t reception_ns);

  // Writers heard within `active_window_ns` before the stop began (stop_began_ns) and not at or after
  // heard_after_ns (the resume minus a margin: samples that arrived before the stop and were taken just after it
  // are not news from after it), and the other writers of their participants not heard after it either. Ordered by
  // topic, participant, writer.
  std::vector<SilentWriter> silent_after(std::int64_t stop_began_ns, std::int64_t active_window_ns,
                                         std::int64_t heard_after_ns) const;

  // Writers heard at or after heard_after_ns (those that reached the recorder again).
  std::size_t heard_after(std::int64_t heard_after_ns) const;

  bool empty() const { return last_.empty(); }

 private:
  struct Key {
    std::string topic, participant, writer;
    bool operator<(const Key& o) const {
      return std::tie(topic, participant, writer) < std::tie(o.topic, o.participant, o.writer);
    }
  };
  std::map<Key, std::int64_t> last_;  // latest reception per writer
};

}  // namespace causal::recorder
