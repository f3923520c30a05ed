#include "causal/dds/outbound_queue.hpp"

#include <algorithm>
#include <stdexcept>

namespace causal::dds {

OutboundQueue::OutboundQueue(std::size_t capacity) : capacity_(capacity) {
  if (capacity == 0) throw std::invalid_argument("outbound queue capacity must be >= 1");
  thread_ = std::thread([this] { run(); });
}

OutboundQueue::~OutboundQueue() {
  abort_.store(true);
  closing_.store(true);
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool OutboundQueue::push(const std::string& stream, Class cls, WriteFn write, const std::atomic<bool>& stop) {
  std::unique_lock<std::mutex> lock(mutex_);
  auto& c = counters_[stream];
  if (abort_.load()) {
    ++c.queued;
    ++c.failed;
    return false;
  }
  while (items_.size() >= capacity_) {
    // Make room by dropping the oldest droppable item, if there is one.
    const auto victim = std::find_if(items_.begin(), items_.end(), [](const Item& i) { return i.cls == Class::Droppable; });
    if (victim != items_.end()) {
      ++counters_[victim->stream].dropped;
      items_.erase(victim);
      break;
    }
    if (cls == Class::Droppable) {  // nothing older to drop: this one goes
      ++c.queued;
      ++c.dropped;
      return true;
    }
    // Full of essential items: wait for the drain thread (bounded by the stop flag, re-checked every 100 ms).
    changed_.wait_for(lock, std::chrono::milliseconds(100));
    if (stop.load()) {
      ++c.failed;
      return false;
    }
  }
  ++c.queued;
  items_.push_back(Item{stream, cls, std::move(write)});
  high_water_ = std::max(high_water_, items_.size());
  changed_.notify_all();
  return true;
}

void OutboundQueue::run() {
  while (true) {
    Item item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return !items_.empty() || closing_.load(); });
      if (items_.empty()) return;  // closing and nothing left
      item = std::move(items_.front());
      items_.pop_front();
      ++in_flight_;
      write_started_ = std::chrono::steady_clock::now();
      changed_.notify_all();
    }
    const WriteResult result = abort_.load() ? WriteResult::Stopped : item.write(abort_);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --in_flight_;
      auto& c = counters_[item.stream];
      if (result == WriteResult::Ok) {
        ++c.written;
      } else {
        ++c.failed;
      }
      changed_.notify_all();
    }
  }
}

void OutboundQueue::abort() {
  abort_.store(true);
  changed_.notify_all();
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return items_.empty() && in_flight_ == 0; });
}

bool OutboundQueue::drain(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [this] { return items_.empty() && in_flight_ == 0; });
}

std::size_t OutboundQueue::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return items_.size() + in_flight_;
}

std::chrono::steady_clock::duration OutboundQueue::blocked_for() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (in_flight_ == 0) return std::chrono::steady_clock::duration::zero();
  return std::chrono::steady_clock::now() - write_started_;
}

std::size_t OutboundQueue::high_water() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return high_water_;
}

std::map<std::string, OutboundQueue::StreamCounters> OutboundQueue::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

}  // namespace causal::dds
