#include "whatif_bridge.hpp"

namespace causal::web {

namespace {
constexpr auto kResendAfter = std::chrono::seconds(1);
}

WhatIfBridge::Outcome WhatIfBridge::ask(const causal_twin::WhatIfRequest& request, std::chrono::milliseconds timeout) {
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

std::vector<causal_twin::WhatIfRequest> WhatIfBridge::due(Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<causal_twin::WhatIfRequest> out;
  for (auto& [id, p] : pending_) {
    if (p.reply || (p.last_sent && now - *p.last_sent < kResendAfter)) continue;
    p.last_sent = now;
    out.push_back(p.request);
  }
  return out;
}

void WhatIfBridge::on_reply(const causal_twin::WhatIfReply& reply) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = pending_.find(reply.request_id());
  if (it == pending_.end() || it->second.reply) return;  // not ours, or a repeated request's second reply
  it->second.reply = reply;
  replied_.notify_all();
}

void WhatIfBridge::stop() {
  std::lock_guard<std::mutex> lock(mutex_);
  stopped_ = true;
  replied_.notify_all();
}

std::uint64_t WhatIfBridge::asked() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return asked_;
}

std::uint64_t WhatIfBridge::answered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return answered_;
}

}  // namespace causal::web
