// OutboundQueue::write_or_push: a message is written on the caller's thread only when nothing is queued or in
// flight and the writer takes it at once; otherwise it is queued behind what came before (order kept), and every
// message is counted exactly once as written.
#include "causal/dds/outbound_queue.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

using causal::dds::OutboundQueue;
using causal::dds::WriteResult;

namespace {

struct Log {
  std::mutex mutex;
  std::vector<int> order;           // message ids in the order they were written
  std::vector<bool> on_caller;      // ... and whether on the caller's thread
  void add(int id, bool caller) {
    std::lock_guard<std::mutex> lock(mutex);
    order.push_back(id);
    on_caller.push_back(caller);
  }
};

}  // namespace

TEST(OutboundQueue, WritesInlineWhenIdleAndQueuesInOrderOtherwise) {
  OutboundQueue q(16);
  std::atomic<bool> stop{false};
  Log log;
  const auto caller = std::this_thread::get_id();
  auto queued_write = [&](int id) {
    return [&, id](const std::atomic<bool>&) {
      log.add(id, std::this_thread::get_id() == caller);
      return WriteResult::Ok;
    };
  };
  auto try_ok = [&](int id) { return [&, id] { log.add(id, std::this_thread::get_id() == caller); return true; }; };
  auto try_refused = [] { return false; };

  // Idle queue, writer takes it: written inline.
  ASSERT_TRUE(q.write_or_push("s", OutboundQueue::Class::Droppable, try_ok(1), queued_write(1), stop));
  // Refused at once: queued, written by the drain thread. A slow queued write keeps the queue busy ...
  std::atomic<bool> release{false};
  ASSERT_TRUE(q.push("s", OutboundQueue::Class::Essential,
                     [&](const std::atomic<bool>&) {
                       while (!release.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
                       log.add(2, std::this_thread::get_id() == caller);
                       return WriteResult::Ok;
                     },
                     stop));
  // ... so the next one may not overtake it, even though its writer would take it at once.
  ASSERT_TRUE(q.write_or_push("s", OutboundQueue::Class::Droppable, try_ok(3), queued_write(3), stop));
  release.store(true);
  ASSERT_TRUE(q.drain(std::chrono::seconds(5)));
  ASSERT_TRUE(q.write_or_push("s", OutboundQueue::Class::Droppable, try_refused, queued_write(4), stop));
  ASSERT_TRUE(q.drain(std::chrono::seconds(5)));

  const std::vector<int> expected_order{1, 2, 3, 4};
  EXPECT_EQ(log.order, expected_order);
  const std::vector<bool> expected_caller{true, false, false, false};
  EXPECT_EQ(log.on_caller, expected_caller);
  const auto counters = q.counters().at("s");
  EXPECT_EQ(counters.queued, 4u);
  EXPECT_EQ(counters.written, 4u);
  EXPECT_EQ(counters.dropped + counters.failed, 0u);
}
