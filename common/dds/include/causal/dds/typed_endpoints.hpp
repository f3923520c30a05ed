// Typed DataWriter / DataReader wrappers created from XML QoS profiles.
#pragma once

#include "causal/dds/participant.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace causal::dds {

using eprosima::fastrtps::types::ReturnCode_t;

// [[nodiscard]]: every function returning it (write, write_until, the queue's write functions) must be looked at:
// a sample not written is counted or logged by its caller, never dropped unseen.
enum class [[nodiscard]] WriteResult { Ok, TimedOut, Stopped, Error };

namespace detail {

// Throws why a DataWriter or DataReader (`kind`) could not be created. Secured, the usual cause is the identity's
// permissions or the governance: a configuration error (std::invalid_argument); otherwise the QoS profile is
// missing (std::runtime_error).
[[noreturn]] inline void endpoint_refused(const Participant& participant, const char* kind,
                                          const std::string& topic_name, const std::string& profile) {
  const std::string what = std::string("cannot create ") + kind + " for '" + topic_name + "'";
  if (participant.secured()) {
    throw std::invalid_argument(what + ": DDS-Security refused it (" + participant.security_note() +
                                "; see the Fast DDS error above)");
  }
  throw std::runtime_error(what + " from QoS profile '" + profile + "' (is the QoS XML loaded?)");
}

}  // namespace detail

template <typename PubSubType>
class TypedWriter {
 public:
  using Sample = typename PubSubType::type;

  // watch_acks: registered with the participant's AckWatch (readers that stop acknowledging raise a HEALTH
  // alarm); false only for the AckWatch's own alarm writer.
  TypedWriter(Participant& participant, const std::string& topic_name, const std::string& profile,
              bool watch_acks = true)
      : participant_(participant) {
    auto* topic = participant.topic<PubSubType>(topic_name);
    // The profile's QoS plus the partitions the identity's grant names (per asset group: group_partitions.hpp).
    eprosima::fastdds::dds::DataWriterQos qos;
    if (participant.publisher()->get_datawriter_qos_from_profile(profile, qos) == ReturnCode_t::RETCODE_OK) {
      participant.add_granted_partitions(topic_name, qos);
      writer_ = participant.publisher()->create_datawriter(topic, qos);
    }
    if (writer_ == nullptr) detail::endpoint_refused(participant, "DataWriter", topic_name, profile);
    auto& m = metrics::process_metrics();
    const metrics::Labels by_topic{{"topic", topic_name}};
    written_ = &m.counter("dds_samples_written_total", "Samples the DDS writer accepted", by_topic);
    refused_ = &m.counter("dds_write_refusals_total",
                          "Write attempts the writer refused for now (reader behind, resource limits), then retried",
                          by_topic);
    abandoned_ = &m.counter("dds_writes_abandoned_total",
                            "Writes given up (deadline, stop or error): the service counts them as failed", by_topic);
    matched_metric_ = m.gauge_callback("dds_matched_readers", "Readers matched by this writer", by_topic,
                                       [w = writer_] {
                                         eprosima::fastdds::dds::PublicationMatchedStatus st;
                                         w->get_publication_matched_status(st);
                                         return static_cast<double>(st.current_count);
                                       });
    if (watch_acks) {
      // KEEP_ALL: an accepted write means the readers made room (acknowledged); KEEP_LAST accepts regardless.
      const bool keep_all = writer_->get_qos().history().kind == eprosima::fastdds::dds::KEEP_ALL_HISTORY_QOS;
      participant.watch_acknowledgments(writer_, topic_name, keep_all ? accepted_at_ : nullptr);
    }
  }
  ~TypedWriter() {
    participant_.unwatch_acknowledgments(writer_);  // before the writer goes: the watch asks it
    matched_metric_.reset();  // before the writer goes: a scrape must not reach it
    participant_.publisher()->delete_datawriter(writer_);
  }
  TypedWriter(const TypedWriter&) = delete;
  TypedWriter& operator=(const TypedWriter&) = delete;

  // Writes one sample. A reliable KEEP_ALL writer blocks (up to the profile's max_blocking_time) while readers
  // are behind, and fails at once when a resource limit is reached (e.g. max_instances); either way it retries,
  // backing off (1 ms doubling to 20 ms, never a busy loop), until the sample is accepted, `stop` is set, or
  // `deadline` passes, so a slow reader never loses data silently and a stop or deadline is seen within
  // max_blocking_time + 20 ms. After a stop, a writer that could not deliver does not block again: later
  // writes while `stop` is set return Stopped at once, so a shutdown that flushes many messages stays bounded.
  WriteResult write_until(Sample& sample, const std::atomic<bool>& stop, std::chrono::steady_clock::time_point deadline) {
    if (stop.load() && blocked_after_stop_) {
      abandoned_->inc();
      return WriteResult::Stopped;
    }
    auto backoff = std::chrono::milliseconds(1);
    while (true) {
      const ReturnCode_t rc = writer_->write(&sample, eprosima::fastrtps::rtps::c_InstanceHandle_Unknown);
      if (rc == ReturnCode_t::RETCODE_OK) {
        written_->inc();
        accepted_at_->store(std::chrono::steady_clock::now().time_since_epoch().count());
        return WriteResult::Ok;
      }
      if (rc != ReturnCode_t::RETCODE_TIMEOUT && rc != ReturnCode_t::RETCODE_OUT_OF_RESOURCES) {
        last_error_ = rc();
        abandoned_->inc();
        return WriteResult::Error;
      }
      last_error_ = rc();
      ++retries_;
      refused_->inc();
      if (stop.load()) {
        blocked_after_stop_ = true;
        abandoned_->inc();
        return WriteResult::Stopped;
      }
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) {
        abandoned_->inc();
        return WriteResult::TimedOut;
      }
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(backoff, deadline - now));
      backoff = std::min(backoff * 2, std::chrono::milliseconds(20));
    }
  }

  // One attempt, no retry: Ok, or TimedOut when the writer refused it (no room in its history: the caller queues
  // it for write_until instead; not counted as a refusal, the queued write is). Waits only as long as the
  // profile's max_blocking_time, so use it on writers whose profile sets 0 (causal_factors_sample_writer).
  WriteResult try_write(Sample& sample) {
    const ReturnCode_t rc = writer_->write(&sample, eprosima::fastrtps::rtps::c_InstanceHandle_Unknown);
    if (rc != ReturnCode_t::RETCODE_OK) return WriteResult::TimedOut;
    written_->inc();
    accepted_at_->store(std::chrono::steady_clock::now().time_since_epoch().count());
    return WriteResult::Ok;
  }

  WriteResult write(Sample& sample, const std::atomic<bool>& stop,
                    std::chrono::milliseconds give_up_after = std::chrono::seconds(60)) {
    return write_until(sample, stop, std::chrono::steady_clock::now() + give_up_after);
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

  // The discovered readers of this writer's topic in participants named `name` (see ParticipantDirectory).
  std::vector<eprosima::fastrtps::rtps::GUID_t> readers_named(const std::string& name) const {
    return participant_.directory().reader_guids_named(writer_->get_topic()->get_name(), name);
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
  // DDS return code of the last failed write attempt (ReturnCode_t value), for diagnostics.
  int last_error() const { return last_error_; }
  // Write attempts the writer refused (full history, resource limits) and that were retried or given up.
  std::uint64_t retries() const { return retries_; }

 private:
  Participant& participant_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  int last_error_ = 0;
  std::uint64_t retries_ = 0;
  bool blocked_after_stop_ = false;
  // steady_clock time of the last accepted write, read by the participant's AckWatch
  std::shared_ptr<std::atomic<std::int64_t>> accepted_at_ = std::make_shared<std::atomic<std::int64_t>>(0);
  metrics::Counter* written_ = nullptr;  // owned by the process registry, which outlives every endpoint
  metrics::Counter* refused_ = nullptr;
  metrics::Counter* abandoned_ = nullptr;
  metrics::CallbackHandle matched_metric_;
};

// "NAME" or "NAME:COUNT": wait for COUNT (default 1) matched readers of participants named NAME.
struct NamedReaders {
  std::string name;
  std::size_t count = 1;
};

[[nodiscard]] inline NamedReaders parse_named_readers(const std::string& spec) {
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

  // With a selection other than every group, the reader subscribes to the topic's content-filtered form
  // (Participant::topic_for_groups): only the selected asset groups' samples reach it.
  TypedReader(Participant& participant, const std::string& topic_name, const std::string& profile,
              const AssetGroupSelection& groups = {})
      : participant_(participant) {
    auto* topic = participant.topic_for_groups<PubSubType>(topic_name, groups);
    eprosima::fastdds::dds::DataReaderQos qos;
    if (participant.subscriber()->get_datareader_qos_from_profile(profile, qos) == ReturnCode_t::RETCODE_OK) {
      participant.add_granted_partitions(topic_name, qos);
      reader_ = participant.subscriber()->create_datareader(topic, qos, &rejections_,
                                                            eprosima::fastdds::dds::StatusMask::sample_rejected());
    }
    if (reader_ == nullptr) detail::endpoint_refused(participant, "DataReader", topic_name, profile);
    reader_->get_statuscondition().set_enabled_statuses(eprosima::fastdds::dds::StatusMask::data_available());
    auto& m = metrics::process_metrics();
    const metrics::Labels by_topic{{"topic", topic_name}};
    received_ = &m.counter("dds_samples_received_total", "Valid samples taken from the DDS reader", by_topic);
    reader_metrics_.push_back(m.gauge_callback("dds_matched_writers", "Writers matched by this reader", by_topic,
                                               [r = reader_] {
                                                 eprosima::fastdds::dds::SubscriptionMatchedStatus st;
                                                 r->get_subscription_matched_status(st);
                                                 return static_cast<double>(st.current_count);
                                               }));
    reader_metrics_.push_back(m.counter_callback("dds_samples_lost_total",
                                                 "Samples this reader never received (DDS sample-lost status)", by_topic,
                                                 [r = reader_] {
                                                   eprosima::fastdds::dds::SampleLostStatus st;
                                                   r->get_sample_lost_status(st);
                                                   return static_cast<double>(st.total_count);
                                                 }));
    auto* limit = &rejections_.instances_limit;
    auto* room = &rejections_.no_room;
    reader_metrics_.push_back(m.counter_callback(
        "dds_samples_rejected_total",
        "Samples the reader refused for good: its instance limit was reached (a new asset group beyond max_instances)",
        {{"topic", topic_name}, {"reason", "instances_limit"}}, [limit] { return static_cast<double>(limit->load()); }));
    // Not loss: a reliable KEEP_ALL reader whose queue is full refuses the sample for now and the writer resends
    // it (back-pressure, seen in normal running at full speed). It was counted as
    // dds_samples_rejected_total{reason="no_room"}, which read like data loss.
    reader_metrics_.push_back(m.counter_callback(
        "dds_samples_deferred_total",
        "Samples the reader had no room for yet (queue full): not lost, the reliable writer resends them (back-pressure)",
        by_topic, [room] { return static_cast<double>(room->load()); }));
  }
  ~TypedReader() {
    reader_metrics_.clear();  // before the reader goes: a scrape must not reach it
    participant_.subscriber()->delete_datareader(reader_);
  }
  TypedReader(const TypedReader&) = delete;
  TypedReader& operator=(const TypedReader&) = delete;

  // Takes every available valid sample and hands it to fn(const Sample&, const SampleInfo&).
  // Returns how many were taken. With `stop`, it returns as soon as stop is set (the rest stays queued), so a
  // reader that is flooded never delays a shutdown.
  template <typename Fn>
  std::size_t take_all(Fn&& fn, const std::atomic<bool>* stop = nullptr) {
    std::size_t taken = 0;
    eprosima::fastdds::dds::SampleInfo info;
    while ((stop == nullptr || !stop->load()) && reader_->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        fn(static_cast<const Sample&>(sample_), static_cast<const eprosima::fastdds::dds::SampleInfo&>(info));
        ++taken;
      }
    }
    received_->inc(static_cast<double>(taken));
    return taken;
  }
  template <typename Fn>
  std::size_t take_all(Fn&& fn, const std::atomic<bool>& stop) {
    return take_all(std::forward<Fn>(fn), &stop);
  }

  // take_all, and the samples without data go to on_state(const SampleInfo&): an instance was disposed by its
  // writer (NOT_ALIVE_DISPOSED) or lost every writer (NOT_ALIVE_NO_WRITERS). Returns the valid samples taken.
  template <typename Fn, typename StateFn>
  std::size_t take_all_and_states(Fn&& fn, StateFn&& on_state, const std::atomic<bool>& stop) {
    std::size_t taken = 0;
    eprosima::fastdds::dds::SampleInfo info;
    while (!stop.load() && reader_->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        fn(static_cast<const Sample&>(sample_), static_cast<const eprosima::fastdds::dds::SampleInfo&>(info));
        ++taken;
      } else {
        on_state(static_cast<const eprosima::fastdds::dds::SampleInfo&>(info));
      }
    }
    received_->inc(static_cast<double>(taken));
    return taken;
  }

  // Samples the reader's resource limits refused (sample_rejected status, counted per sample by a listener),
  // so a refusal is never silent. For lack of room (max_samples, max_samples_per_instance; Fast DDS also counts
  // the writer's samples still missing before it against the per-instance room, so many interleaved instances
  // and a retransmission can trigger it) a reliable writer resends the sample later: nothing is lost, but
  // throughput suffers. A sample of an instance beyond max_instances has no room at all.
  struct Rejections {
    std::uint64_t instances_limit = 0;  // REJECTED_BY_INSTANCES_LIMIT: that instance is not served
    std::uint64_t no_room = 0;          // REJECTED_BY_SAMPLES_LIMIT / _PER_INSTANCE_LIMIT: resent by reliable writers
    std::uint64_t total() const { return instances_limit + no_room; }
  };
  Rejections rejections() const { return {rejections_.instances_limit.load(), rejections_.no_room.load()}; }

  std::size_t matched_writers() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return static_cast<std::size_t>(status.current_count);
  }

  // Writers ever matched (cumulative: also one that came and left between two looks).
  std::size_t matched_writers_total() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return static_cast<std::size_t>(status.total_count);
  }

  // Samples this reader never received (e.g. evicted by a writer before it got them). Cumulative.
  std::uint64_t lost_samples() const {
    eprosima::fastdds::dds::SampleLostStatus status;
    reader_->get_sample_lost_status(status);
    return static_cast<std::uint64_t>(status.total_count);
  }

  eprosima::fastdds::dds::DataReader* get() const { return reader_; }

 private:
  // Called by Fast DDS once per refused sample, on its receive thread.
  struct RejectionCounter : eprosima::fastdds::dds::DataReaderListener {
    std::atomic<std::uint64_t> instances_limit{0}, no_room{0};
    void on_sample_rejected(eprosima::fastdds::dds::DataReader*,
                            const eprosima::fastdds::dds::SampleRejectedStatus& status) override {
      if (status.last_reason == eprosima::fastdds::dds::REJECTED_BY_INSTANCES_LIMIT) {
        ++instances_limit;
      } else {
        ++no_room;
      }
    }
  };

  Participant& participant_;
  RejectionCounter rejections_;  // outlives reader_ (deleted in the destructor body)
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  Sample sample_;  // reused: frames are large, do not reallocate per take
  metrics::Counter* received_ = nullptr;  // owned by the process registry, which outlives every endpoint
  std::vector<metrics::CallbackHandle> reader_metrics_;
};

}  // namespace causal::dds
