// A bounded queue between a service's processing loop and its DDS writers, drained by its own thread, so the
// processing (the Kalman filters) never waits on the bus: a reliable writer blocks while a reader is behind
// (until the reader catches up or its lease expires), and that wait happens here, not in the filter loop.
//
// Overflow policy (stated in README "Delivery contract"):
//  * items are Essential (condition vectors, condition-level factors, alarms) or Droppable (sample-level
//    factor vectors, a high-rate diagnostic stream);
//  * when the queue holds `capacity` items and another arrives, the OLDEST Droppable item is dropped and
//    counted per stream;
//  * Essential items are never dropped: when the queue is full of them, push() waits until there is room
//    (the service then stops taking input, so back-pressure reaches the source) or the stop flag is set;
//  * an item whose write fails (the writer gave up, or a DDS error) is counted as failed per stream.
// Every count is visible through counters(), ends up in the service's exit summary, and is exported as
// Prometheus metrics (outbound_messages_total{stream,outcome}, outbound_queue_depth).
#pragma once

#include "causal/dds/typed_endpoints.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace causal::dds {

class OutboundQueue {
 public:
  enum class Class { Essential, Droppable };
  // Writes one message; returns the writer's result. Runs on the drain thread.
  using WriteFn = std::function<WriteResult(const std::atomic<bool>& stop)>;

  struct StreamCounters {
    std::uint64_t queued = 0, written = 0, dropped = 0, failed = 0;
  };

  explicit OutboundQueue(std::size_t capacity);
  ~OutboundQueue();  // stops the drain thread; call drain() first to deliver what is queued
  OutboundQueue(const OutboundQueue&) = delete;
  OutboundQueue& operator=(const OutboundQueue&) = delete;

  // Queues one write. `stream` names what is counted (e.g. "causal_factors/sample"). Returns false when the
  // item could not be queued because `stop` was set while waiting for room (counted as failed).
  bool push(const std::string& stream, Class cls, WriteFn write, const std::atomic<bool>& stop);

  // Writes on the caller's thread when nothing is queued or being written and `try_write` (one attempt that does
  // not wait: a writer with max_blocking_time 0) succeeds; otherwise queues `write` as push() does. This saves
  // the hand-off to the drain thread, a wake-up that on a loaded host waits for a free core (measured: the largest
  // stage of the frames whose factors were late, docs/scale-and-benchmarks.md "Latency spikes"). Order is kept
  // for one producer: an item is written inline only when everything pushed before it has been written.
  bool write_or_push(const std::string& stream, Class cls, const std::function<bool()>& try_write, WriteFn write,
                     const std::atomic<bool>& stop);

  // Waits until everything queued has been written (or failed), or `timeout` passes. True when empty.
  bool drain(std::chrono::milliseconds timeout);
  // Gives up: the write in progress is abandoned and every queued item is counted as failed (waits until the
  // drain thread has let go of them). Call when the service must end now (signal, max runtime).
  void abort();

  std::size_t size() const;
  // How long the write in progress has been waiting (a reader not acknowledging); zero when none waits.
  std::chrono::steady_clock::duration blocked_for() const;
  std::size_t high_water() const;
  std::map<std::string, StreamCounters> counters() const;

 private:
  struct Item {
    std::string stream;
    Class cls;
    WriteFn write;
  };
  void run();
  // The registry's counters of `stream` (created once; called with mutex_ held).
  struct StreamMetrics {
    metrics::Counter *written = nullptr, *dropped = nullptr, *failed = nullptr;
  };
  StreamMetrics& metrics_of(const std::string& stream);
  void count(const std::string& stream, StreamCounters& c, std::uint64_t StreamCounters::*field);
  void update_depth() { depth_.store(items_.size() + in_flight_); }

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  // Two conditions: the drain thread waits on work_ (an item queued, or closing), everyone else on changed_
  // (room freed, a write done). With one, every inline write's notify woke the idle drain thread for nothing:
  // 2 wake-ups and context switches per frame in causal-estimator (docs/scale-and-benchmarks.md).
  std::condition_variable work_;
  std::condition_variable changed_;
  std::deque<Item> items_;
  std::size_t in_flight_ = 0;
  std::chrono::steady_clock::time_point write_started_;  // of the write in progress (in_flight_ == 1)
  std::size_t high_water_ = 0;
  std::map<std::string, StreamCounters> counters_;
  std::atomic<bool> closing_{false};
  std::atomic<bool> abort_{false};  // the stop flag of every write
  std::map<std::string, StreamMetrics> metrics_;
  std::atomic<std::size_t> depth_{0};  // items_ + in flight, for the metrics scrape (which must not lock)
  metrics::CallbackHandle depth_metric_;
  std::thread thread_;
};

}  // namespace causal::dds
