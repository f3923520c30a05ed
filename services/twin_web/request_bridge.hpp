// A web thread's request handed to the DDS thread and its result handed back: the pattern of WhatIfBridge and
// AlarmActionBridge as one template for any request and result type (the approve button's ApprovalBridge is one).
// A web thread calls ask() and waits (bounded); the DDS thread takes the requests that are due with
// due() and sends them, and passes every result it has to on_result(). A request without a result a second after
// its last send is due again with the same request id (a receiver answers a repeated id once).
//   Request and Result: anything with request_id() (IDL types, or a plain struct with that member function).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace causal::web {

template <typename Request, typename Result>
class RequestBridge {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Status { Answered, NoReply, Stopped };
  struct Outcome {
    Status status = Status::NoReply;
    Result result;  // valid when Answered
  };

  // Web thread: sends `request` (its id must be unique among those waiting) and waits up to `timeout`.
  Outcome ask(const Request& request, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    Outcome out;
    if (stopped_) {
      out.status = Status::Stopped;
      return out;
    }
    ++asked_;
    const std::string id = request.request_id();
    pending_[id] = Pending{request, std::nullopt, std::nullopt};
    answered_cv_.wait_for(lock, timeout, [&] { return stopped_ || pending_[id].result.has_value(); });
    Pending& p = pending_[id];
    if (p.result) {
      out.status = Status::Answered;
      out.result = *p.result;
      ++answered_;
    } else {
      out.status = stopped_ ? Status::Stopped : Status::NoReply;
    }
    pending_.erase(id);
    return out;
  }

  // DDS thread: requests to send now (new ones, and those without a result a second after their last send).
  std::vector<Request> due(Clock::time_point now) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Request> out;
    for (auto& [id, p] : pending_) {
      if (p.result || (p.last_sent && now - *p.last_sent < kResendAfter)) continue;
      p.last_sent = now;
      out.push_back(p.request);
    }
    return out;
  }

  // DDS thread: a result; one no waiting request asked for is ignored (another sender's, or a repeat's).
  void on_result(const Result& result) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = pending_.find(result.request_id());
    if (it == pending_.end() || it->second.result) return;
    it->second.result = result;
    answered_cv_.notify_all();
  }

  // Wakes every waiting asker with Stopped; later asks return Stopped at once.
  void stop() {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    answered_cv_.notify_all();
  }

  std::uint64_t asked() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return asked_;
  }
  std::uint64_t answered() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return answered_;
  }

 private:
  static constexpr auto kResendAfter = std::chrono::seconds(1);
  struct Pending {
    Request request;
    std::optional<Clock::time_point> last_sent;
    std::optional<Result> result;
  };
  mutable std::mutex mutex_;
  std::condition_variable answered_cv_;
  std::map<std::string, Pending> pending_;  // by request id
  bool stopped_ = false;
  std::uint64_t asked_ = 0, answered_ = 0;
};

}  // namespace causal::web
