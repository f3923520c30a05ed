// A hard runtime limit that holds even while the service's own thread is blocked (e.g. in a DDS write that
// waits for a slow reader): a small thread sleeps until the deadline and then calls on_expiry once, typically
// the same stop() a SIGTERM calls. Destroying the timer first cancels it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace causal::dds {

class StopTimer {
 public:
  // after_s <= 0: no limit (no thread is started).
  StopTimer(double after_s, std::function<void()> on_expiry) {
    if (after_s <= 0.0) return;
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(after_s));
    thread_ = std::thread([this, deadline, on_expiry = std::move(on_expiry)] {
      std::unique_lock<std::mutex> lock(mutex_);
      if (wake_.wait_until(lock, deadline, [this] { return cancelled_; })) return;
      expired_.store(true);
      lock.unlock();
      on_expiry();
    });
  }
  ~StopTimer() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      cancelled_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  StopTimer(const StopTimer&) = delete;
  StopTimer& operator=(const StopTimer&) = delete;

  bool expired() const { return expired_.load(); }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool cancelled_ = false;
  std::atomic<bool> expired_{false};
  std::thread thread_;
};

}  // namespace causal::dds
