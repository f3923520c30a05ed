// Hands requests from the web threads to the DDS thread and their replies back, for every request/reply pair
// the page sends over DDS (what-if questions, alarm actions). A web thread calls ask() and waits (bounded); the
// DDS thread takes the requests that are due with due() and sends them, and passes every reply it reads to
// on_reply(). Replies are volatile on DDS: a reply sent before the answering writer has matched our reader is
// lost, so a request is repeated once a second with the same id (the answering service answers a repeated id
// with its first reply and applies it once) until its reply comes or its asker gives up.
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

// Request and Reply are IDL types with a request_id() each; a reply belongs to the request with its id.
template <typename Request, typename Reply>
class RequestBridge {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr auto kResendAfter = std::chrono::seconds(1);
  enum class Status { Answered, NoReply, Stopped };
  struct Outcome {
    Status status = Status::NoReply;
    Reply reply;  // valid when Answered (the reply itself may still be a refusal)
  };

  // Web thread: sends `request` (its id must be unique) and waits up to `timeout` for the reply.
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
    replied_.wait_for(lock, timeout, [&] { return stopped_ || pending_[id].reply.has_value(); });
    Pending& p = pending_[id];
    if (p.reply) {
      out.status = Status::Answered;
      out.reply = *p.reply;
      ++answered_;
    } else {
      out.status = stopped_ ? Status::Stopped : Status::NoReply;
    }
    pending_.erase(id);
    return out;
  }

  // DDS thread: requests to send now (new ones, and those not answered within a second of their last send).
  std::vector<Request> due(Clock::time_point now) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Request> out;
    for (auto& [id, p] : pending_) {
      if (p.reply || (p.last_sent && now - *p.last_sent < kResendAfter)) continue;
      p.last_sent = now;
      out.push_back(p.request);
    }
    return out;
  }

  // DDS thread: a reply read from DDS; one that answers no waiting request is ignored (another asker's), and so
  // is a repeated request's second reply.
  void on_reply(const Reply& reply) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = pending_.find(reply.request_id());
    if (it == pending_.end() || it->second.reply) return;
    it->second.reply = reply;
    replied_.notify_all();
  }

  // Wakes every waiting asker with Stopped; later asks return Stopped at once.
  void stop() {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    replied_.notify_all();
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
  struct Pending {
    Request request;
    std::optional<Clock::time_point> last_sent;
    std::optional<Reply> reply;
  };
  mutable std::mutex mutex_;
  std::condition_variable replied_;
  std::map<std::string, Pending> pending_;  // by request id
  bool stopped_ = false;
  std::uint64_t asked_ = 0, answered_ = 0;
};

}  // namespace causal::web
