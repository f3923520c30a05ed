#include "causal/dds/event_loop.hpp"

#include <fastdds/dds/core/condition/StatusCondition.hpp>

#include "causal/dds/systemd_notify.hpp"

#include <algorithm>
#include <thread>

namespace causal::dds {

EventLoop::EventLoop() { waitset_.attach_condition(guard_); }

EventLoop::~EventLoop() {
  for (auto* condition : attached_) waitset_.detach_condition(*condition);
  waitset_.detach_condition(guard_);
}

void EventLoop::attach(eprosima::fastdds::dds::DataReader* reader) {
  auto& condition = reader->get_statuscondition();
  waitset_.attach_condition(condition);
  attached_.push_back(&condition);
}

bool EventLoop::wait(std::chrono::milliseconds timeout) {
  if (stopped_.load()) return false;
  eprosima::fastdds::dds::ConditionSeq active;
  const auto secs = std::chrono::duration_cast<std::chrono::seconds>(timeout);
  const auto nsecs = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout - secs);
  waitset_.wait(active, eprosima::fastrtps::Duration_t(static_cast<int32_t>(secs.count()),
                                                        static_cast<uint32_t>(nsecs.count())));
  return !stopped_.load();
}

void EventLoop::stop() {
  stopped_.store(true);
  guard_.set_trigger_value(true);
}

RunEnd EventLoop::run(const RunLimits& limits, const std::function<std::size_t()>& poll,
                      const std::function<std::size_t()>& sources) {
  using Clock = std::chrono::steady_clock;
  const auto started = Clock::now();
  // Watchdog: max-runtime must hold even when the loop thread is stuck in a blocking write.
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  std::atomic<bool> expired{false};
  std::thread watchdog;
  if (limits.max_runtime_s > 0) {
    const auto deadline = started + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(limits.max_runtime_s));
    watchdog = std::thread([&] {
      std::unique_lock<std::mutex> lock(mutex);
      if (!done_cv.wait_until(lock, deadline, [&] { return done; })) {
        expired.store(true);
        stop();
      }
    });
  }
  // The service's entities exist and it takes data from now on (systemd Type=notify units start here).
  notify_systemd("READY=1\nSTATUS=running");
  auto last_data = started;
  auto sources_left = started;  // when the last source left (idle time counts from the later of the two)
  bool any_data = false, had_sources = true;
  RunEnd end = RunEnd::Stopped;
  while (wait(std::chrono::milliseconds(200))) {
    const std::size_t n = poll();
    const auto now = Clock::now();
    if (n > 0) {
      last_data = now;
      any_data = true;
    }
    const bool has_sources = sources() > 0;
    if (!any_data && limits.sources_came && limits.sources_came()) any_data = true;
    if (had_sources && !has_sources) sources_left = now;
    had_sources = has_sources;
    // A process that was frozen (SIGSTOP) wakes up with old timestamps: it is not idle until its sources
    // have been gone, and nothing has arrived, for the whole idle time.
    const auto quiet_since = std::max(last_data, sources_left);
    if (limits.idle_exit_s > 0 && any_data && !has_sources &&
        std::chrono::duration<double>(now - quiet_since).count() > limits.idle_exit_s) {
      end = RunEnd::Idle;
      break;
    }
  }
  if (watchdog.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
    }
    done_cv.notify_all();
    watchdog.join();
  }
  if (end != RunEnd::Idle && expired.load()) end = RunEnd::MaxRuntime;
  notify_systemd("STOPPING=1");  // draining and checkpointing follow; systemd waits up to TimeoutStopSec
  return end;
}

}  // namespace causal::dds
