#include "causal/dds/event_loop.hpp"

#include <fastdds/dds/core/condition/StatusCondition.hpp>

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

}  // namespace causal::dds
