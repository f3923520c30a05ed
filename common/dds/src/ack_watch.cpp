#include "causal/dds/ack_watch.hpp"

#include "causal/io/time_format.hpp"

#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/metrics/metrics_registry.hpp"
#include "causal_twinPubSubTypes.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>

namespace causal::dds {

namespace {
using Clock = std::chrono::steady_clock;

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : "; ") + x;
  return s;
}
}  // namespace

struct AckWatch::Watched {
  eprosima::fastdds::dds::DataWriter* writer = nullptr;
  std::string topic;
  Clock::time_point acked_at;              // last time every matched reader had acknowledged everything
  std::optional<causal_twin::Alarm> open;  // the raised alarm, until the readers acknowledge again
  std::shared_ptr<const std::atomic<std::int64_t>> accepted_at;  // KEEP_ALL writers: last accepted write
  metrics::Counter* stalls = nullptr;
};

AckWatch::AckWatch(Participant& participant, double stall_after_s)
    : participant_(participant), stall_after_s_(stall_after_s) {
  if (stall_after_s_ > 0.0) thread_ = std::thread([this] { run(); });
}

AckWatch::~AckWatch() {
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (stalls_.load() > 0) spdlog::warn("summary ack_stalls={} (readers that stopped acknowledging)", stalls_.load());
}

void AckWatch::watch(eprosima::fastdds::dds::DataWriter* writer, const std::string& topic,
                     std::shared_ptr<const std::atomic<std::int64_t>> accepted_at) {
  auto w = std::make_unique<Watched>();
  w->accepted_at = std::move(accepted_at);
  w->writer = writer;
  w->topic = topic;
  w->acked_at = Clock::now();
  w->stalls = &metrics::process_metrics().counter(
      "dds_ack_stalls_total", "Times the matched readers of a reliable writer stopped acknowledging (HEALTH alarm)",
      {{"topic", topic}});
  std::lock_guard<std::mutex> lock(mutex_);
  watched_.push_back(std::move(w));
}

void AckWatch::unwatch(eprosima::fastdds::dds::DataWriter* writer) {
  std::lock_guard<std::mutex> lock(mutex_);
  watched_.erase(std::remove_if(watched_.begin(), watched_.end(), [&](const auto& w) { return w->writer == writer; }),
                 watched_.end());
}

void AckWatch::run() {
  while (true) {
    {
      std::unique_lock<std::mutex> lock(wake_mutex_);
      if (wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; })) return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& w : watched_) check(*w, Clock::now());
  }
}

void AckWatch::check(Watched& w, Clock::time_point now) {
  eprosima::fastdds::dds::PublicationMatchedStatus matched;
  w.writer->get_publication_matched_status(matched);
  // No reader: nothing to wait for. Otherwise: has every reader acknowledged everything at some moment?
  bool progress = matched.current_count == 0 ||
                  w.writer->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(0, 200000000)) ==
                      ReturnCode_t::RETCODE_OK;
  if (progress) {
    w.acked_at = Clock::now();
  } else if (w.accepted_at) {
    const Clock::time_point accepted{Clock::duration(w.accepted_at->load())};
    if (accepted > w.acked_at) {  // KEEP_ALL: room was made, so the readers acknowledge
      w.acked_at = accepted;
      progress = true;
    }
  }
  if (progress) {
    if (w.open) {
      w.open->state(causal_twin::CLEARED);
      w.open->cleared_time_ns(io::utc_now_ns());
      w.open->reason("the readers of " + w.topic + " acknowledge again" +
                     (matched.current_count == 0 ? " (none is matched now)" : ""));
      spdlog::info("HEALTH CLEARED {}: {}", w.open->alarm_id(), w.open->reason());
      publish(*w.open);
      w.open.reset();
    }
    return;
  }
  const double waited = std::chrono::duration<double>(now - w.acked_at).count();
  if (w.open || waited < stall_after_s_) return;
  const auto readers = participant_.directory().reader_descriptions(w.topic);
  const std::string self = participant_.directory().name_of(participant_.get()->guid().guidPrefix);
  causal_twin::Alarm a;
  const auto now_ns = io::utc_now_ns();
  a.alarm_id(self + "/" + w.topic + "/reader_not_acknowledging/t" + std::to_string(now_ns / 1000000000));
  a.kind("reader_not_acknowledging");
  a.category("health");
  a.severity(causal_twin::WARNING);
  a.state(causal_twin::RAISED);
  a.raised_time_ns(now_ns);
  a.channel_name(w.topic);
  a.score(waited);
  a.threshold(stall_after_s_);
  a.reason(fmt::format(
      "{}: the {} matched reader(s) of {} have not all acknowledged for {:.1f} s (this process: {}); readers: {}. A "
      "reader in a process of another user on this host cannot acknowledge over shared memory: use the shipped "
      "profile (UDP loopback)",
      self, matched.current_count, w.topic, waited, process_description(),
      readers.empty() ? std::string("none discovered") : joined(readers)));
  spdlog::warn("HEALTH RAISED {}: {}", a.alarm_id(), a.reason());
  w.stalls->inc();
  ++stalls_;
  w.open = a;
  publish(a);
}

void AckWatch::publish(const causal_twin::Alarm& alarm) {
  using AlarmWriter = TypedWriter<causal_twin::AlarmPubSubType>;
  try {
    if (!alarm_writer_) {
      alarm_writer_ = std::make_shared<AlarmWriter>(participant_, topics::kAlarm, profiles::kAlarmWriter, false);
    }
    causal_twin::Alarm copy = alarm;
    std::atomic<bool> no_stop{false};
    // Keep-last per id: never blocks on the stalled reader.
    if (static_cast<AlarmWriter*>(alarm_writer_.get())->write(copy, no_stop, std::chrono::seconds(1)) != WriteResult::Ok)
      spdlog::error("the reader_not_acknowledging alarm {} could not be published within 1 s", alarm.alarm_id());
  } catch (const std::exception& e) {
    spdlog::error("the reader_not_acknowledging alarm could not be published: {}", e.what());
  }
}

}  // namespace causal::dds
