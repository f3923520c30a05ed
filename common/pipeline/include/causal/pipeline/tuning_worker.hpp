// One background thread that runs the automatic noise tuning of factor streams (FactorStream), so a stream
// that is still tuning does not hold up the thread feeding every other stream.
//
// Tasks run one at a time in the order submitted (one thread: start-up tuning of many groups does not take
// more than one extra core from the processing thread). A task's result is read back through the future
// submit() returns; the stream polls it at its next feed and waits for it only at finish(). Results are the
// same as on the caller's thread: the task is a pure function of the copied calibration window.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

namespace causal::pipeline {

class TuningWorker {
 public:
  TuningWorker();
  ~TuningWorker();  // finishes the task running, drops the queued ones (their streams are gone), joins
  TuningWorker(const TuningWorker&) = delete;
  TuningWorker& operator=(const TuningWorker&) = delete;

  template <class F>
  auto submit(F&& f) -> std::future<decltype(f())> {
    using R = decltype(f());
    auto task = std::make_shared<std::packaged_task<R()>>(std::forward<F>(f));
    std::future<R> result = task->get_future();
    enqueue([task] { (*task)(); });
    return result;
  }

  // Tests: while held, submitted tasks wait (so a stream's "still tuning" state can be exercised).
  void hold(bool held);
  std::size_t submitted() const;  // tasks submitted so far (statistics, tests)

 private:
  void enqueue(std::function<void()> job);
  void loop();

  mutable std::mutex mutex_;
  std::condition_variable work_;
  std::deque<std::function<void()>> jobs_;
  std::size_t submitted_ = 0;
  bool held_ = false;
  bool closing_ = false;
  std::thread thread_;  // last: starts after the members it uses
};

}  // namespace causal::pipeline
