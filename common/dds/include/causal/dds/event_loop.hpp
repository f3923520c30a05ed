// One WaitSet over the readers a service listens to, plus a guard condition that stop() triggers,
// so a service thread sleeps until data arrives or it is asked to stop (no polling, no busy wait).
// Declare it AFTER the readers it watches: it detaches their conditions when destroyed, first.
#pragma once

#include <fastdds/dds/core/condition/GuardCondition.hpp>
#include <fastdds/dds/core/condition/WaitSet.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>

#include <atomic>
#include <chrono>
#include <vector>

namespace causal::dds {

class EventLoop {
 public:
  EventLoop();
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  void attach(eprosima::fastdds::dds::DataReader* reader);
  // Waits until a reader has data, stop() is called, or the timeout passes. Returns false once stopped.
  bool wait(std::chrono::milliseconds timeout);
  void stop();
  bool stopped() const { return stopped_.load(); }
  const std::atomic<bool>& stop_flag() const { return stopped_; }

 private:
  eprosima::fastdds::dds::WaitSet waitset_;
  eprosima::fastdds::dds::GuardCondition guard_;
  std::vector<eprosima::fastdds::dds::Condition*> attached_;
  std::atomic<bool> stopped_{false};
};

}  // namespace causal::dds
