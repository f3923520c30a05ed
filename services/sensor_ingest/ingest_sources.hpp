// Where sensor-ingest's messages come from: an MQTT broker (libmosquitto), UDP datagrams, or stdin. Each
// source runs on its own thread and hands whole messages to a bounded MessageQueue; when the queue is full
// the source waits (MQTT: the broker holds QoS 1 messages; UDP: the kernel buffer, then datagrams are lost
// there; stdin: the writing process blocks), so memory stays bounded.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "ingest_options.hpp"

struct mosquitto;
struct mosquitto_message;

namespace causal::ingest {

class MessageQueue {
 public:
  explicit MessageQueue(std::size_t capacity) : capacity_(capacity) {}
  // Waits while full; false (message dropped) once the queue is closed.
  bool push(std::string message);
  // The next message, or nullopt after `timeout` or when closed and empty.
  std::optional<std::string> pop(std::chrono::milliseconds timeout);
  void close();  // no more messages: pop() drains, then returns nullopt at once
  bool closed_and_empty() const;

 private:
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::string> messages_;
  bool closed_ = false;
};

class MessageSource {
 public:
  virtual ~MessageSource() = default;
  virtual void start() = 0;  // begins delivering into the queue given at construction
  virtual void stop() = 0;   // no message is delivered after it returns
};

// Builds the source for a spec. The stdin source closes the queue at end of input.
std::unique_ptr<MessageSource> make_source(const IngestOptions& options, MessageQueue& queue);

class MqttSource : public MessageSource {
 public:
  MqttSource(const IngestOptions& options, MessageQueue& queue);
  ~MqttSource() override;
  void start() override;
  void stop() override;

 private:
  // The network loop on its own thread: connect, serve, and after any failure (broker down at start, broker
  // restarted) try again every second until stopped. (libmosquitto's own loop thread does not retry a first
  // connection that failed, so the adapter could not start before its broker.)
  void run();
  void secure(const MqttSecurity& security);  // TLS and user name from the options; throws std::invalid_argument
  bool pause(std::chrono::milliseconds d);  // false once stopping
  static void on_connect(struct mosquitto* m, void* self, int rc);
  static void on_disconnect(struct mosquitto* m, void* self, int rc);
  static void on_message(struct mosquitto* m, void* self, const struct mosquitto_message* msg);

  SourceSpec spec_;
  int qos_;
  MessageQueue& queue_;
  struct mosquitto* client_ = nullptr;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
  std::uint64_t connects_ = 0;
};

}  // namespace causal::ingest
