#include "causal/dds/outbound_queue.hpp"

#include <algorithm>
#include <stdexcept>

namespace causal::dds {

OutboundQueue::OutboundQueue(std::size_t capacity) : capacity_(capacity) {
  if (capacity == 0) throw std::invalid_argument("outbound queue capacity must be >= 1");
  depth_metric_ = metrics::process_metrics().gauge_callback(
      "outbound_queue_depth", "Messages waiting between the filters and the DDS writers (queued and in flight)", {},
      [this] { return static_cast<double>(depth_.load()); });
  thread_ = std::thread([this] { run(); });
}

OutboundQueue::~OutboundQueue() {
  abort_.store(true);
  closing_.store(true);
  { std::lock_guard<std::mutex> lock(mutex_); }  // the drain thread is either waiting or sees closing_
  work_.notify_all();
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
  depth_metric_.reset();
}

OutboundQueue::StreamMetrics& OutboundQueue::metrics_of(const std::string& stream) {
  auto [it, inserted] = metrics_.try_emplace(stream);
  if (inserted) {
    auto& m = metrics::process_metrics();
    const char* help = "Messages through the outbound queue by outcome (dropped: oldest droppable on overflow; "
                       "failed: the write was given up)";
    it->second.written = &m.counter("outbound_messages_total", help, {{"stream", stream}, {"outcome", "written"}});
    it->second.dropped = &m.counter("outbound_messages_total", help, {{"stream", stream}, {"outcome", "dropped"}});
    it->second.failed = &m.counter("outbound_messages_total", help, {{"stream", stream}, {"outcome", "failed"}});
  }
  return it->second;
}

void OutboundQueue::count(const std::string& stream, StreamCounters& c, std::uint64_t StreamCounters::*field) {
  ++(c.*field);
  StreamMetrics& m = metrics_of(stream);
  if (field == &StreamCounters::written) m.written->inc();
  else if (field == &StreamCounters::dropped) m.dropped->inc();
  else if (field == &StreamCounters::failed) m.failed->inc();
}

bool OutboundQueue::push(const std::string& stream, Class cls, WriteFn write, const std::atomic<bool>& stop) {
  std::unique_lock<std::mutex> lock(mutex_);
  auto& c = counters_[stream];
  if (abort_.load()) {
    ++c.queued;
    count(stream, c, &StreamCounters::failed);
    return false;
  }
  while (items_.size() >= capacity_) {
    // Make room by dropping the oldest droppable item, if there is one.
    const auto victim = std::find_if(items_.begin(), items_.end(), [](const Item& i) { return i.cls == Class::Droppable; });
    if (victim != items_.end()) {
      count(victim->stream, counters_[victim->stream], &StreamCounters::dropped);
      items_.erase(victim);
      break;
    }
    if (cls == Class::Droppable) {  // nothing older to drop: this one goes
      ++c.queued;
      count(stream, c, &StreamCounters::dropped);
      return true;
    }
    // Full of essential items: wait for the drain thread (bounded by the stop flag, re-checked every 100 ms).
    changed_.wait_for(lock, std::chrono::milliseconds(100));
    if (stop.load()) {
      count(stream, c, &StreamCounters::failed);
      return false;
    }
  }
  ++c.queued;
  items_.push_back(Item{stream, cls, std::move(write)});
  high_water_ = std::max(high_water_, items_.size());
  update_depth();
  work_.notify_one();  // only the drain thread waits for items; nobody waiting on changed_ gains from one more
  return true;
}

bool OutboundQueue::write_or_push(const std::string& stream, Class cls, const std::function<bool()>& try_write,
                                  WriteFn write, const std::atomic<bool>& stop) {
  bool inline_write = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // Only with nothing ahead of it (and a queue that has not given up); otherwise in order, through the queue.
    if (!abort_.load() && items_.empty() && in_flight_ == 0) {
      ++in_flight_;  // holds the drain thread's place: what is pushed meanwhile waits behind this write
      write_started_ = std::chrono::steady_clock::now();
      inline_write = true;
    }
  }
  if (inline_write) {
    const bool written = try_write();
    std::lock_guard<std::mutex> lock(mutex_);
    --in_flight_;
    if (written) {
      auto& c = counters_[stream];
      ++c.queued;
      count(stream, c, &StreamCounters::written);
    }
    update_depth();
    changed_.notify_all();
    if (written) return true;
  }
  return push(stream, cls, std::move(write), stop);
}

void OutboundQueue::run() {
  while (true) {
    Item item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_.wait(lock, [this] { return !items_.empty() || closing_.load(); });
      if (items_.empty()) return;  // closing and nothing left
      item = std::move(items_.front());
      items_.pop_front();
      ++in_flight_;
      write_started_ = std::chrono::steady_clock::now();
      update_depth();
      changed_.notify_all();
    }
    const WriteResult result = abort_.load() ? WriteResult::Stopped : item.write(abort_);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --in_flight_;
      auto& c = counters_[item.stream];
      count(item.stream, c, result == WriteResult::Ok ? &StreamCounters::written : &StreamCounters::failed);
      update_depth();
      changed_.notify_all();
    }
  }
}

void OutboundQueue::abort() {
  abort_.store(true);
  work_.notify_all();
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
