#include "causal/dds/event_loop.hpp"

#include "causal/io/time_format.hpp"

#include <fastdds/dds/core/condition/StatusCondition.hpp>

#include "causal/dds/systemd_notify.hpp"

#include <spdlog/spdlog.h>

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
  // Watchdog thread: max-runtime must hold even when the loop thread is stuck in a blocking write; and it notices
  // when the whole process did not run (its 200 ms sleep lasted kSuspendedAfter or more), whatever the loop thread
  // was doing at the time (SIGSTOP in the middle of a poll as well as in a wait).
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  std::atomic<bool> expired{false};
  const bool has_deadline = limits.max_runtime_s > 0;
  const auto deadline = started + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(has_deadline ? limits.max_runtime_s : 0.0));
  std::thread watchdog([&] {
    std::unique_lock<std::mutex> lock(mutex);
    auto last_tick = Clock::now();
    while (!done) {
      auto wake = Clock::now() + std::chrono::milliseconds(200);
      if (has_deadline) wake = std::min(wake, deadline);
      done_cv.wait_until(lock, wake, [&] { return done; });
      const auto now = Clock::now();
      if (now - last_tick >= kSuspendedAfter) {
        ++suspension_.count;
        suspension_.last_seconds = std::chrono::duration<double>(now - last_tick).count();
        suspension_.last_resumed_at = now;
        suspension_.last_resumed_at_unix_ns = io::utc_now_ns();
        spdlog::warn("this process did not run for {:.1f} s (stopped or not scheduled): its peers may have dropped "
                     "it meanwhile (their lease of it expired), and what they published then is missing here",
                     suspension_.last_seconds);
      }
      last_tick = now;
      if (!done && has_deadline && now >= deadline) {
        expired.store(true);
        stop();
        return;
      }
    }
  });
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
  {
    std::lock_guard<std::mutex> lock(mutex);
    done = true;
  }
  done_cv.notify_all();
  watchdog.join();  // suspension_ is read only after run() returns
  if (end != RunEnd::Idle && expired.load()) end = RunEnd::MaxRuntime;
  notify_systemd("STOPPING=1");  // draining and checkpointing follow; systemd waits up to TimeoutStopSec
  return end;
}

}  // namespace causal::dds
