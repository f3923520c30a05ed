// One WaitSet over the readers a service listens to, plus a guard condition that stop() triggers,
// so a service thread sleeps until data arrives or it is asked to stop (no polling, no busy wait).
// Declare it AFTER the readers it watches: it detaches their conditions when destroyed, first.
#pragma once

#include <fastdds/dds/core/condition/GuardCondition.hpp>
#include <fastdds/dds/core/condition/WaitSet.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

namespace causal::dds {

// When a service's run loop ends by itself (0 = never).
struct RunLimits {
  double idle_exit_s = 0.0;    // once data has arrived, every source has left and nothing came for this long
  double max_runtime_s = 0.0;  // hard stop, honoured even while a write is blocked
  // Set: idle also without data once this returns true (sources were matched, even between two polls) and
  // they have all left: a reader filtered to part of the data (an estimator shard) may be sent nothing at all.
  // Unset: a service waits for data before it can be idle.
  std::function<bool()> sources_came;
};

enum class RunEnd { Stopped, Idle, MaxRuntime };

// A wait that returned far later than asked: the process was stopped (SIGSTOP, a debugger) or not scheduled.
// Its peers may have dropped it meanwhile (their lease of it expired), so what they published then is missing.
struct Suspension {
  std::uint64_t count = 0;   // 0: never
  double last_seconds = 0.0;  // how long the last one lasted
  std::chrono::steady_clock::time_point last_resumed_at{};
  std::int64_t last_resumed_at_unix_ns = 0;  // the same instant on the system clock (DDS reception timestamps)
};

class EventLoop {
 public:
  EventLoop();
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  void attach(eprosima::fastdds::dds::DataReader* reader);
  // Waits until a reader has data, stop() is called, or the timeout passes. Returns false once stopped.
  bool wait(std::chrono::milliseconds timeout);
  void stop();
  bool stopped() const { return stopped_.load(); }

  // The run loop every service shares: waits for data, calls poll() (returns how many items it handled), and
  // ends when stop() is called (a signal), when limits.max_runtime_s passes (a watchdog calls stop(), so a
  // write that is blocked on a slow reader is abandoned too), or when idle: data has arrived, sources()
  // (matched upstream writers) is 0 and nothing arrived for limits.idle_exit_s. Tells systemd READY=1 when it
  // starts and STOPPING=1 when it ends (systemd_notify.hpp; nothing outside systemd).
  RunEnd run(const RunLimits& limits, const std::function<std::size_t()>& poll,
             const std::function<std::size_t()>& sources);
  const std::atomic<bool>& stop_flag() const { return stopped_; }
  // Waits in run() that returned kSuspendedAfter or more after they began (the timeout is 200 ms).
  static constexpr std::chrono::seconds kSuspendedAfter{3};
  const Suspension& suspension() const { return suspension_; }

 private:
  eprosima::fastdds::dds::WaitSet waitset_;
  eprosima::fastdds::dds::GuardCondition guard_;
  std::vector<eprosima::fastdds::dds::Condition*> attached_;
  std::atomic<bool> stopped_{false};
  Suspension suspension_;
};

}  // namespace causal::dds
