// Hands the page's alarm actions (acknowledge, shelve, unshelve) from the web threads to the DDS thread and
// alarm-recommender's results back, as WhatIfBridge does for what-if questions. An action not answered within a
// second is sent again with the same request id: the recommender answers a repeated id with its first result and
// applies it once.
#pragma once

#include "causal_twin.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace causal::web {

class AlarmActionBridge {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Status { Answered, NoReply, Stopped };
  struct Outcome {
    Status status = Status::NoReply;
    causal_twin::AlarmActionResult result;  // valid when Answered (result.applied() may be false: refused)
  };

  // Web thread: sends `action` (its request id must be unique) and waits up to `timeout` for the result.
  Outcome act(const causal_twin::AlarmAction& action, std::chrono::milliseconds timeout);
  // DDS thread: actions to send now (new ones, and those without a result a second after their last send).
  std::vector<causal_twin::AlarmAction> due(Clock::time_point now);
  // DDS thread: a result read from DDS; one no waiting action asked for is ignored (another sender's).
  void on_result(const causal_twin::AlarmActionResult& result);
  void stop();

  std::uint64_t asked() const;
  std::uint64_t answered() const;

 private:
  struct Pending {
    causal_twin::AlarmAction action;
    std::optional<Clock::time_point> last_sent;
    std::optional<causal_twin::AlarmActionResult> result;
  };
  mutable std::mutex mutex_;
  std::condition_variable answered_cv_;
  std::map<std::string, Pending> pending_;  // by request id
  bool stopped_ = false;
  std::uint64_t asked_ = 0, answered_ = 0;
};

}  // namespace causal::web
