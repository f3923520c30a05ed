#include "causal/dds/writer_grant_check.hpp"

#include "causal/dds/group_partitions.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <sstream>

namespace causal::dds {
namespace {

std::string listed(const std::optional<std::vector<std::string>>& names) {
  std::string joined;
  if (names) {
    for (const auto& p : *names) joined += (joined.empty() ? "" : ", ") + (p.empty() ? std::string("''") : p);
  }
  return joined;
}

}  // namespace

WriterGrantCheck::WriterGrantCheck(const ParticipantDirectory& directory, std::string part, std::string what,
                                   std::string who_is_granted)
    : directory_(directory), part_(std::move(part)), what_(std::move(what)),
      who_is_granted_(std::move(who_is_granted)) {}

std::string WriterGrantCheck::reason(const eprosima::fastrtps::rtps::GUID_t& writer, const std::string& who) const {
  const auto partitions = directory_.writer_partitions(writer);
  const auto changed = directory_.writer_partitions_changed(writer);
  const std::string participant = directory_.name_of(writer.guidPrefix);
  if (changed) {
    return fmt::format("writer {} of participant '{}' changed its partitions after discovery, from [{}] to [{}] "
                       "(refused from then on)", who, participant, listed(partitions), listed(changed));
  }
  if (partitions) {
    return fmt::format("writer {} of participant '{}' may write only its partitions [{}]", who, participant,
                       listed(partitions));
  }
  return fmt::format("writer {} was never discovered (its grant is unknown)", who);
}

bool WriterGrantCheck::entitled(const std::string& asset_group, const eprosima::fastrtps::rtps::GUID_t& writer) {
  const auto partitions = directory_.writer_partitions(writer);
  // Discovery reports a writer (with its partitions) before Fast DDS matches it, so every sample's writer is
  // known; one that is not is refused like a writer without the grant.
  if (!directory_.writer_partitions_changed(writer) && partitions && partitions_allow_group(*partitions, asset_group)) {
    return true;
  }
  ++refused_;
  std::ostringstream text;
  text << writer;
  const std::string who = text.str();
  const bool first_of_pair = pairs_.size() < kMaxPairs && pairs_.insert(who + "|" + asset_group).second;
  if (!first_of_pair) {
    if (refused_ % 1000 == 0) {
      spdlog::error("{} {}s refused so far: their writers may not write their asset group", refused_, what_);
    }
    return false;
  }
  const std::string why = reason(writer, who);
  spdlog::error("asset group '{}' refused from this writer: {} ({}); its {} is refused (counted, exit 4)", asset_group,
                why, who_is_granted_, what_);
  causal_twin::Alarm alarm;
  const std::int64_t now = io::utc_now_ns();
  // Wall-clock time and a serial: a refusal has no source index of its own.
  alarm.alarm_id(fmt::format("{}/{}/group_not_entitled/t{}.{}", asset_group, part_, now / 1000000000, pairs_.size()));
  alarm.asset_group(asset_group);
  alarm.kind("group_not_entitled");
  alarm.category("health");
  alarm.severity(causal_twin::CRITICAL);
  alarm.state(causal_twin::RAISED);
  alarm.raised_time_ns(now);
  alarm.score(static_cast<double>(refused_));
  alarm.threshold(0.0);
  alarm.reason(what_ + " for asset group '" + asset_group + "' refused: " + why + "; an identity is granted only " +
               "its own asset groups (" + who_is_granted_ + ")");
  alarms_.push_back(std::move(alarm));
  return false;
}

std::vector<causal_twin::Alarm> WriterGrantCheck::take_alarms() {
  std::vector<causal_twin::Alarm> out;
  out.swap(alarms_);
  return out;
}

}  // namespace causal::dds
