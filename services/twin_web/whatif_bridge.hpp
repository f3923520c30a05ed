// Hands what-if questions from the web threads to the DDS thread and the replies back. A web thread calls
// ask() and waits (bounded); the DDS thread takes the requests that are due with due() and sends them, and
// passes every reply it reads to on_reply(). Replies are volatile on DDS: a reply sent before the recommender's
// writer has matched our reader is lost, so a request is repeated once a second (same id, as causal-ask does)
// until its reply comes or its asker gives up.
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

class WhatIfBridge {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Status { Answered, NoReply, Stopped };
  struct Outcome {
    Status status = Status::NoReply;
    causal_twin::WhatIfReply reply;  // valid when Answered (reply.ok() may still be false: a refusal)
  };

  // Web thread: sends `request` (its id must be unique) and waits up to `timeout` for the reply.
  Outcome ask(const causal_twin::WhatIfRequest& request, std::chrono::milliseconds timeout);

  // DDS thread: requests to send now (new ones, and those not answered within a second of their last send).
  std::vector<causal_twin::WhatIfRequest> due(Clock::time_point now);
  // DDS thread: a reply read from DDS; one that answers no waiting request is ignored (another asker's).
  void on_reply(const causal_twin::WhatIfReply& reply);
  // Wakes every waiting asker with Stopped; later asks return Stopped at once.
  void stop();

  std::uint64_t asked() const;
  std::uint64_t answered() const;

 private:
  struct Pending {
    causal_twin::WhatIfRequest request;
    std::optional<Clock::time_point> last_sent;
    std::optional<causal_twin::WhatIfReply> reply;
  };
  mutable std::mutex mutex_;
  std::condition_variable replied_;
  std::map<std::string, Pending> pending_;  // by request id
  bool stopped_ = false;
  std::uint64_t asked_ = 0, answered_ = 0;
};

}  // namespace causal::web
