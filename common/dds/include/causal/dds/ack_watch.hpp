// Reliable writers whose readers stop acknowledging, detected within seconds and named.
//
// Why: a reader that never acknowledges while its participant stays alive holds a reliable writer for ever
// (KEEP_ALL: the history fills and write() blocks; KEEP_LAST: the reader silently falls behind). Seen: a
// causal-ask run as root on the services' host could not send its acknowledgements over shared memory (Fast
// DDS segments are per user), its participant announced itself over UDP and stayed matched, and the services'
// traffic stalled; the only signal was a source_silent alarm 900 s later, blaming the sensor. The lease (5 s)
// does not help: the participant is alive.
//
// How (Fast DDS 2.9 has no "reader not acknowledging" status and no per-reader acknowledgement API): a thread
// asks every watched writer with DataWriter::wait_for_acknowledgments(200 ms) whether every matched reader has
// acknowledged every sample at some moment. A healthy reader reaches that state many times a second even under
// a continuous stream (the call returns as soon as the last acknowledgement arrives); a writer that has not
// reached it for `stall_after_s` while it had matched readers is stalled: a HEALTH alarm on causal_twin/alarm
// (kind reader_not_acknowledging, channel_name = the topic, the matched readers named with their process, user
// and host as they announce them), a log line, and the metric dds_ack_stalls_total{topic}. It is cleared when
// the readers acknowledge again (or leave). The alarm writer is created on the first stall only, so a process
// that never stalls has no extra endpoint.
#pragma once

#include "causal/dds/participant.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace causal_twin {
class Alarm;
}

namespace causal::dds {

class AckWatch {
 public:
  // stall_after_s <= 0: no watch (writers are registered and ignored).
  AckWatch(Participant& participant, double stall_after_s);
  ~AckWatch();
  AckWatch(const AckWatch&) = delete;
  AckWatch& operator=(const AckWatch&) = delete;

  // accepted_at (KEEP_ALL writers, else null): steady_clock time of the last accepted write. A KEEP_ALL writer
  // under back-pressure is never fully acknowledged, but each accepted write means a reader freed room, so it
  // counts as progress; a stalled reader blocks the writes once the instance's history is full (64 frames).
  void watch(eprosima::fastdds::dds::DataWriter* writer, const std::string& topic,
             std::shared_ptr<const std::atomic<std::int64_t>> accepted_at);
  void unwatch(eprosima::fastdds::dds::DataWriter* writer);  // before the writer is deleted

  std::uint64_t stalls() const { return stalls_.load(); }  // alarms raised so far

 private:
  struct Watched;
  void run();
  void check(Watched& w, std::chrono::steady_clock::time_point now);
  void publish(const causal_twin::Alarm& alarm);

  Participant& participant_;
  double stall_after_s_;
  std::mutex mutex_;  // watched_ (held while a writer is asked: unwatch waits for the question to end)
  std::vector<std::unique_ptr<Watched>> watched_;
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::atomic<std::uint64_t> stalls_{0};
  std::shared_ptr<void> alarm_writer_;  // TypedWriter<AlarmPubSubType>, made on the first stall
  std::thread thread_;
};

}  // namespace causal::dds
