#include "causal/pipeline/tuning_worker.hpp"

namespace causal::pipeline {

TuningWorker::TuningWorker() : thread_([this] { loop(); }) {}

TuningWorker::~TuningWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
    held_ = false;
  }
  work_.notify_all();
  thread_.join();
}

void TuningWorker::enqueue(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
    ++submitted_;
  }
  work_.notify_one();
}

void TuningWorker::hold(bool held) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = held;
  }
  work_.notify_all();
}

std::size_t TuningWorker::submitted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return submitted_;
}

void TuningWorker::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_.wait(lock, [this] { return closing_ || (!held_ && !jobs_.empty()); });
    // Closing: the streams that submitted the queued tasks are gone (each holds the worker), so no one waits
    // for their results; a shutdown does not tune every group that never started.
    if (closing_) return;
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    job();  // a packaged_task: an exception is stored in its future, never thrown here
    lock.lock();
  }
}

}  // namespace causal::pipeline
