#include "causal/dds/health_watch.hpp"

#include "causal/io/time_format.hpp"

#include <fastdds/dds/subscriber/InstanceState.hpp>

#include <algorithm>
#include <chrono>

namespace causal::dds {

namespace {

std::array<unsigned char, 16> key_of(const eprosima::fastrtps::rtps::InstanceHandle_t& h) {
  std::array<unsigned char, 16> k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<unsigned char>(h.value[i]);
  return k;
}

}  // namespace

HealthWatch::HealthWatch(double deadline_s, std::string what, std::string watched, std::vector<std::string> topics)
    : health_(deadline_s), what_(std::move(what)), watched_(std::move(watched)), topics_(std::move(topics)) {}

void HealthWatch::on_sample(const std::string& source, std::uint64_t snapshot_index,
                            const eprosima::fastdds::dds::SampleInfo& info) {
  sources_[key_of(info.instance_handle)] = source;
  writers_[source] = info.sample_identity.writer_guid().guidPrefix;
  health_.on_data(source, snapshot_index, SourceHealth::Clock::now(), changes_);
  convert(changes_);
}

void HealthWatch::on_sample(const std::string& source, const eprosima::fastdds::dds::SampleInfo& info) {
  sources_[key_of(info.instance_handle)] = source;
  writers_[source] = info.sample_identity.writer_guid().guidPrefix;
  health_.on_data(source, SourceHealth::Clock::now(), changes_);
  convert(changes_);
}

void HealthWatch::on_state(const eprosima::fastdds::dds::SampleInfo& info) {
  const auto it = sources_.find(key_of(info.instance_handle));
  if (it == sources_.end()) {
    ++unknown_instances_;  // no data of it ever reached us: nothing to watch
    return;
  }
  const auto now = SourceHealth::Clock::now();
  if (info.instance_state == eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) {
    health_.on_ended(it->second, now, changes_);
  } else if (info.instance_state == eprosima::fastdds::dds::NOT_ALIVE_NO_WRITERS_INSTANCE_STATE) {
    health_.on_writer_lost(it->second, now, changes_);
  }
  convert(changes_);
}

void HealthWatch::check(const ParticipantDirectory& directory) {
  const auto now = SourceHealth::Clock::now();
  departures_.clear();
  directory.departures_since(departures_seen_, departures_);
  for (const auto& d : departures_) {
    std::size_t others = 0;  // writers of our topics still alive (a restarted source, a standby)
    if (d.dropped) {
      for (const auto& t : topics_) others += directory.live_writers(t);
    }
    for (const auto& [source, prefix] : writers_) {
      if (prefix != d.prefix) continue;
      if (d.dropped && others == 0) {
        health_.on_writer_lost(source, now, changes_);
      } else if (d.dropped) {
        continue;  // another writer may carry on: the deadline decides
      } else {
        health_.on_ended(source, now, changes_);
      }
    }
  }
  health_.check(now, changes_);
  convert(changes_);
}

std::vector<causal_twin::Alarm> HealthWatch::take_alarms() {
  std::vector<causal_twin::Alarm> out;
  out.swap(alarms_);
  return out;
}

void HealthWatch::convert(std::vector<HealthChange>& changes) {
  for (auto& c : changes) {
    const std::int64_t now_ns = io::utc_now_ns();
    if (c.kind == HealthChange::Kind::Cleared) {
      const auto it = open_.find(c.source);
      if (it == open_.end()) continue;
      causal_twin::Alarm a = it->second;
      a.state(causal_twin::CLEARED);
      a.cleared_time_ns(now_ns);
      a.reason(c.reason);
      alarms_.push_back(std::move(a));
      open_.erase(it);
      continue;
    }
    causal_twin::Alarm a;
    a.alarm_id(c.source + "/" + watched_ + "/health/s" + (c.has_index ? std::to_string(c.last_index) : std::string("none")));
    a.asset_group(c.source);
    a.channel(0);
    a.severity(causal_twin::WARNING);
    a.state(causal_twin::RAISED);
    a.kind("source_silent");
    a.category("health");
    a.raised_time_ns(now_ns);
    a.sample_index(c.last_index);
    a.score(c.silent_s);                  // seconds silent when raised
    a.threshold(health_.deadline_s());    // the deadline (0 = none: the writer was lost)
    a.channel_name(watched_);
    a.reason(what_ + ": " + c.reason);
    open_[c.source] = a;
    alarms_.push_back(std::move(a));
  }
  changes.clear();
}

}  // namespace causal::dds
