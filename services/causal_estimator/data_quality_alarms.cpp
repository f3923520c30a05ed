#include "data_quality_alarms.hpp"

namespace causal::estimator {

namespace {

std::string key_of(const std::string& group, int channel, const std::string& kind) {
  return group + '\x1f' + std::to_string(channel) + '\x1f' + kind;
}

}  // namespace

void DataQualityAlarms::on_events(const std::string& asset_group, const std::vector<std::string>& channel_names,
                                  const std::vector<pipeline::QualityEvent>& events, std::uint64_t snapshot_index,
                                  std::int64_t time_ns, std::vector<causal_twin::Alarm>& out) {
  using Kind = pipeline::QualityEventKind;
  for (const auto& e : events) {
    if (e.kind == Kind::MachineStopped || e.kind == Kind::MachineRunning) {
      on_operating_state(asset_group, e, snapshot_index, time_ns, out);
      continue;
    }
    const bool bad_value = e.kind == Kind::NonFinite || e.kind == Kind::OutOfRange;
    const std::string kind = bad_value ? pipeline::to_string(e.kind) : "channel_quarantined";
    // The two screens (raw rows, ready-made condition vectors) are told apart in key and id, as the alarm engines'
    // time scales are: one must never clear or overwrite the other's alarm.
    const bool sample = e.level == pipeline::ScreenLevel::Sample;
    const std::string key = key_of(asset_group, e.channel, std::string(sample ? "sample/" : "") + kind);
    if (e.kind == Kind::Recovered) {
      clear(key, snapshot_index, time_ns, e.reason, out);
      continue;
    }
    auto it = open_.find(key);
    if (it != open_.end()) {  // already raised: remember that it is still happening
      it->second.seen_in_snapshot = true;
      continue;
    }
    const std::string name = e.channel >= 0 && static_cast<std::size_t>(e.channel) < channel_names.size()
                                 ? channel_names[static_cast<std::size_t>(e.channel)]
                                 : std::to_string(e.channel + 1);
    causal_twin::Alarm a;
    a.alarm_id(unique_id(asset_group + (sample ? "/sample/" : "/") + name + "/" + kind + "/s" +
                         std::to_string(snapshot_index)));
    a.asset_group(asset_group);
    a.channel(static_cast<uint16_t>(e.channel + 1));
    a.channel_name(name);
    a.severity(bad_value ? causal_twin::ADVISORY : causal_twin::WARNING);
    a.state(causal_twin::RAISED);
    a.kind(kind);
    a.category("data_quality");
    a.raised_time_ns(time_ns);
    a.sample_index(snapshot_index);
    a.score(static_cast<double>(e.count));
    a.reason(e.reason + (bad_value ? " (rejected: the value is not used; other channels carry on)"
                                   : " (channel quarantined: its values are not used until it recovers)"));
    out.push_back(a);
    open_.emplace(key, Open{a, bad_value, true});
    ++raised_;
  }
}

bool DataQualityAlarms::on_refused(const std::string& asset_group, const std::string& reason,
                                   std::uint64_t snapshot_index, std::int64_t time_ns,
                                   std::vector<causal_twin::Alarm>& out) {
  const std::string kind = "input_refused";
  const std::string key = key_of(asset_group, -1, kind);
  if (open_.count(key) > 0) return false;
  causal_twin::Alarm a;
  a.alarm_id(unique_id(asset_group + "/input/" + kind + "/s" + std::to_string(snapshot_index)));
  a.asset_group(asset_group);
  a.channel(0);  // the whole group
  a.channel_name("");
  a.severity(causal_twin::CRITICAL);
  a.state(causal_twin::RAISED);
  a.kind(kind);
  a.category("data_quality");
  a.raised_time_ns(time_ns);
  a.sample_index(snapshot_index);
  a.score(1.0);
  a.reason("the estimator refuses this asset group's input, it is not analysed: " + reason);
  out.push_back(a);
  open_.emplace(key, Open{a, false, true});
  ++raised_;
  return true;
}

std::string DataQualityAlarms::unique_id(const std::string& id) {
  // Raised twice in one snapshot (a channel quarantined, released and quarantined again): ".2", ".3", ...
  std::uint64_t& n = issued_[id];
  return ++n == 1 ? id : id + "." + std::to_string(n);
}

std::map<std::string, DataQualityAlarms::Open>::iterator DataQualityAlarms::clear(
    std::map<std::string, Open>::iterator it, std::uint64_t snapshot_index, std::int64_t time_ns,
    const std::string& reason, std::vector<causal_twin::Alarm>& out) {
  it->second.msg.state(causal_twin::CLEARED);
  it->second.msg.cleared_time_ns(time_ns);
  it->second.msg.sample_index(snapshot_index);
  it->second.msg.reason(reason);
  out.push_back(it->second.msg);
  return open_.erase(it);
}

void DataQualityAlarms::clear(const std::string& key, std::uint64_t snapshot_index, std::int64_t time_ns,
                              const std::string& reason, std::vector<causal_twin::Alarm>& out) {
  const auto it = open_.find(key);
  if (it != open_.end()) clear(it, snapshot_index, time_ns, reason, out);
}

void DataQualityAlarms::on_operating_state(const std::string& asset_group, const pipeline::QualityEvent& e,
                                           std::uint64_t snapshot_index, std::int64_t time_ns,
                                           std::vector<causal_twin::Alarm>& out) {
  const std::string key = key_of(asset_group, -1, "machine_stopped");
  const auto it = open_.find(key);
  if (e.kind == pipeline::QualityEventKind::MachineRunning) {
    clear(key, snapshot_index, time_ns, e.reason, out);
    return;
  }
  if (it != open_.end()) return;
  // An operating state, not a fault in the data: category operating_change, open while the machine stands.
  causal_twin::Alarm a;
  a.alarm_id(unique_id(asset_group + "/machine/machine_stopped/s" + std::to_string(snapshot_index)));
  a.asset_group(asset_group);
  a.channel(0);  // the whole group
  a.severity(causal_twin::ADVISORY);
  a.state(causal_twin::RAISED);
  a.kind("machine_stopped");
  a.category("operating_change");
  a.raised_time_ns(time_ns);
  a.sample_index(snapshot_index);
  a.score(1.0);
  a.reason(e.reason + " (an operating state: its data is analysed, nothing is refused)");
  out.push_back(a);
  open_.emplace(key, Open{a, false, true});
  ++stopped_;
}

void DataQualityAlarms::end_of_snapshot(const std::string& asset_group, std::uint64_t snapshot_index,
                                        std::int64_t time_ns, std::vector<causal_twin::Alarm>& out) {
  const std::string prefix = asset_group + '\x1f';
  for (auto it = open_.lower_bound(prefix); it != open_.end() && it->first.compare(0, prefix.size(), prefix) == 0;) {
    Open& o = it->second;
    if (o.bad_value && !o.seen_in_snapshot) {
      it = clear(it, snapshot_index, time_ns, "no bad value in snapshot " + std::to_string(snapshot_index), out);
      continue;
    }
    o.seen_in_snapshot = false;
    ++it;
  }
}

}  // namespace causal::estimator
