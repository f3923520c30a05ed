// Typed DataWriter / DataReader wrappers created from XML QoS profiles.
#pragma once

#include "causal/dds/participant.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace causal::dds {

using eprosima::fastrtps::types::ReturnCode_t;

enum class WriteResult { Ok, TimedOut, Stopped, Error };

template <typename PubSubType>
class TypedWriter {
 public:
  using Sample = typename PubSubType::type;

  TypedWriter(Participant& participant, const std::string& topic_name, const std::string& profile)
      : participant_(participant) {
    auto* topic = participant.topic<PubSubType>(topic_name);
    writer_ = participant.publisher()->create_datawriter_with_profile(topic, profile);
    if (writer_ == nullptr) {
      throw std::runtime_error("cannot create DataWriter for '" + topic_name + "' from QoS profile '" + profile +
                               "' (is the QoS XML loaded?)");
    }
  }
  ~TypedWriter() { participant_.publisher()->delete_datawriter(writer_); }
  TypedWriter(const TypedWriter&) = delete;
  TypedWriter& operator=(const TypedWriter&) = delete;

  // Writes one sample. A reliable KEEP_ALL writer blocks while readers are behind; it retries until the
  // sample is accepted, `stop` is set, or `give_up_after` passes, so a slow reader never loses data silently.
  WriteResult write(Sample& sample, const std::atomic<bool>& stop,
                    std::chrono::milliseconds give_up_after = std::chrono::seconds(60)) {
    const auto deadline = std::chrono::steady_clock::now() + give_up_after;
    while (true) {
      const ReturnCode_t rc = writer_->write(&sample, eprosima::fastrtps::rtps::c_InstanceHandle_Unknown);
      if (rc == ReturnCode_t::RETCODE_OK) return WriteResult::Ok;
      if (rc != ReturnCode_t::RETCODE_TIMEOUT && rc != ReturnCode_t::RETCODE_OUT_OF_RESOURCES) {
        last_error_ = rc();
        return WriteResult::Error;
      }
      if (stop.load()) return WriteResult::Stopped;
      if (std::chrono::steady_clock::now() >= deadline) return WriteResult::TimedOut;
    }
  }

  std::size_t matched_readers() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return static_cast<std::size_t>(status.current_count);
  }

  // Waits (bounded) until at least `count` readers are matched. Returns false on timeout or stop.
  bool wait_for_readers(std::size_t count, std::chrono::milliseconds timeout, const std::atomic<bool>& stop) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (matched_readers() < count) {
      if (stop.load() || std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  // Readers of this writer's topic in participants named `name` (the services name their participants after
  // themselves: "causal-estimator", "alarm-recommender", ...), as discovery knows them; capped by the number
  // of matched readers, so a reader that is discovered but not (yet) matched does not count.
  std::size_t matched_readers_named(const std::string& name) const {
    const std::size_t named = participant_.directory().readers_named(writer_->get_topic()->get_name(), name);
    return std::min(named, matched_readers());
  }

  // Waits (bounded) until at least `count` readers of participants named `name` are matched. A reader of any
  // other participant (a recorder, a test observer) does not count: data must not start flowing before the
  // consumer that needs it is there. Returns false on timeout or stop.
  bool wait_for_named_readers(const std::string& name, std::size_t count, std::chrono::milliseconds timeout,
                              const std::atomic<bool>& stop) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (matched_readers_named(name) < count) {
      if (stop.load() || std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  // Blocks until every matched reader acknowledged every sample (or timeout): call before exiting.
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout) {
    const auto secs = std::chrono::duration_cast<std::chrono::seconds>(timeout);
    const auto nsecs = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout - secs);
    eprosima::fastrtps::Duration_t d(static_cast<int32_t>(secs.count()), static_cast<uint32_t>(nsecs.count()));
    return writer_->wait_for_acknowledgments(d) == ReturnCode_t::RETCODE_OK;
  }

  eprosima::fastdds::dds::DataWriter* get() const { return writer_; }
  // DDS return code of the last failed write (ReturnCode_t value), for diagnostics.
  int last_error() const { return last_error_; }

 private:
  Participant& participant_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  int last_error_ = 0;
};

// "NAME" or "NAME:COUNT": wait for COUNT (default 1) matched readers of participants named NAME.
struct NamedReaders {
  std::string name;
  std::size_t count = 1;
};

inline NamedReaders parse_named_readers(const std::string& spec) {
  NamedReaders r;
  const auto colon = spec.rfind(':');
  r.name = spec.substr(0, colon);
  if (colon != std::string::npos) {
    const std::string n = spec.substr(colon + 1);
    if (n.empty() || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) == 0) {
      throw std::invalid_argument("'" + spec + "': expected NAME or NAME:COUNT with COUNT >= 1");
    }
    r.count = std::stoul(n);
  }
  if (r.name.empty()) throw std::invalid_argument("'" + spec + "': empty participant name");
  return r;
}

// Waits (bounded, total) until every named reader set is matched on `writer`. Returns the first that is not
// (empty name when all are there).
template <typename Writer>
std::string wait_for_named_readers(const Writer& writer, const std::vector<NamedReaders>& wanted,
                                   std::chrono::milliseconds timeout, const std::atomic<bool>& stop) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (const auto& w : wanted) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (!writer.wait_for_named_readers(w.name, w.count, std::max(left, std::chrono::milliseconds(0)), stop)) {
      return w.name;
    }
  }
  return {};
}

template <typename PubSubType>
class TypedReader {
 public:
  using Sample = typename PubSubType::type;

  TypedReader(Participant& participant, const std::string& topic_name, const std::string& profile)
      : participant_(participant) {
    auto* topic = participant.topic<PubSubType>(topic_name);
    reader_ = participant.subscriber()->create_datareader_with_profile(topic, profile);
    if (reader_ == nullptr) {
      throw std::runtime_error("cannot create DataReader for '" + topic_name + "' from QoS profile '" + profile +
                               "' (is the QoS XML loaded?)");
    }
    reader_->get_statuscondition().set_enabled_statuses(eprosima::fastdds::dds::StatusMask::data_available());
  }
  ~TypedReader() { participant_.subscriber()->delete_datareader(reader_); }
  TypedReader(const TypedReader&) = delete;
  TypedReader& operator=(const TypedReader&) = delete;

  // Takes every available valid sample and hands it to fn(const Sample&, const SampleInfo&).
  // Returns how many were taken.
  template <typename Fn>
  std::size_t take_all(Fn&& fn) {
    std::size_t taken = 0;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        fn(static_cast<const Sample&>(sample_), static_cast<const eprosima::fastdds::dds::SampleInfo&>(info));
        ++taken;
      }
    }
    return taken;
  }

  std::size_t matched_writers() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return static_cast<std::size_t>(status.current_count);
  }

  // Samples DDS could not deliver to this reader: rejected (resource limits) and lost (never received, e.g.
  // evicted by a writer before this reader got them). Cumulative; services report them, never ignore them.
  std::uint64_t rejected_samples() const {
    eprosima::fastdds::dds::SampleRejectedStatus status;
    reader_->get_sample_rejected_status(status);
    return static_cast<std::uint64_t>(status.total_count);
  }
  std::uint64_t lost_samples() const {
    eprosima::fastdds::dds::SampleLostStatus status;
    reader_->get_sample_lost_status(status);
    return static_cast<std::uint64_t>(status.total_count);
  }

  eprosima::fastdds::dds::DataReader* get() const { return reader_; }

 private:
  Participant& participant_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  Sample sample_;  // reused: frames are large, do not reallocate per take
};

}  // namespace causal::dds
