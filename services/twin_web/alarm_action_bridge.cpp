#include "alarm_action_bridge.hpp"

namespace causal::web {

namespace {
constexpr auto kResendAfter = std::chrono::seconds(1);
}

AlarmActionBridge::Outcome AlarmActionBridge::act(const causal_twin::AlarmAction& action,
                                                  std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  Outcome out;
  if (stopped_) {
    out.status = Status::Stopped;
    return out;
  }
  ++asked_;
  const std::string id = action.request_id();
  pending_[id] = Pending{action, std::nullopt, std::nullopt};
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

std::vector<causal_twin::AlarmAction> AlarmActionBridge::due(Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<causal_twin::AlarmAction> out;
  for (auto& [id, p] : pending_) {
    if (p.result || (p.last_sent && now - *p.last_sent < kResendAfter)) continue;
    p.last_sent = now;
    out.push_back(p.action);
  }
  return out;
}

void AlarmActionBridge::on_result(const causal_twin::AlarmActionResult& result) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = pending_.find(result.request_id());
  if (it == pending_.end() || it->second.result) return;
  it->second.result = result;
  answered_cv_.notify_all();
}

void AlarmActionBridge::stop() {
  std::lock_guard<std::mutex> lock(mutex_);
  stopped_ = true;
  answered_cv_.notify_all();
}

std::uint64_t AlarmActionBridge::asked() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return asked_;
}

std::uint64_t AlarmActionBridge::answered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return answered_;
}

}  // namespace causal::web
