#include "approval_keeper.hpp"

#include "causal/dds/group_partitions.hpp"
#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

namespace causal::web {

namespace {
std::string recommendation_key(const causal_twin::Intervention& iv) {
  return iv.asset_group() + "\n" + iv.recommendation_id();
}
}  // namespace

ApprovalKeeper::ApprovalKeeper(dds::Participant& participant)
    : writer_(participant, dds::topics::kIntervention, dds::profiles::kInterventionWriter),
      grants_(participant.directory(), "intervention", "approval",
              "issue-identity.sh: the approving operator's grant names the asset group") {
  // The partitions the writer announces (its grant's, Participant::add_granted_partitions): the endpoint property
  // "partitions", names joined by ';'; none on an open bus (every group).
  eprosima::fastdds::dds::DataWriterQos qos;
  writer_.get()->get_qos(qos);
  for (const auto& p : qos.properties().properties()) {
    if (p.name() != "partitions") continue;
    std::string rest = p.value();
    for (std::size_t at = rest.find(';'); at != std::string::npos; at = rest.find(';')) {
      own_partitions_.push_back(rest.substr(0, at));
      rest.erase(0, at + 1);
    }
    own_partitions_.push_back(rest);
  }
}

bool ApprovalKeeper::on_read(const causal_twin::Intervention& in, const eprosima::fastrtps::rtps::GUID_t& writer) {
  if (writer == writer_.get()->guid()) return true;  // ours: granted when it was written
  if (!grants_.entitled(in.asset_group(), writer)) {
    ++counts_.not_entitled;
    (void)grants_.take_alarms();  // twin-web writes no alarms: logged by the check, counted here and in the summary
    return false;
  }
  if (written_.count(in.request_id()) > 0) return true;  // kept already
  for (const auto& queued : copies_) {
    if (queued.request_id() == in.request_id()) return true;
  }
  copies_.push_back(in);
  return true;
}

std::string ApprovalKeeper::keep(causal_twin::Intervention& iv, const std::atomic<bool>& stop) {
  if (!dds::partitions_allow_group(own_partitions_, iv.asset_group())) {
    return "twin-web's identity is not granted asset group '" + iv.asset_group() + "'";
  }
  if (writer_.write(iv, stop, std::chrono::milliseconds(500)) != dds::WriteResult::Ok) {
    return "not written (DDS return code " + std::to_string(writer_.last_error()) + ")";
  }
  written_.insert(iv.request_id());
  by_recommendation_.emplace(recommendation_key(iv), iv.request_id());
  return {};
}

ApprovalResult ApprovalKeeper::approve(causal_twin::Intervention& iv, const std::atomic<bool>& stop) {
  ApprovalResult r;
  r.id = iv.request_id();
  // One approval per recommendation, whoever made it: a second click (or a second operator) is refused, so the
  // plant never receives two overlapping changes for one piece of advice. The same request id again is the same
  // approval: answered as published.
  if (written_.count(iv.request_id()) > 0) {
    r.published = true;
  } else if (const auto it = by_recommendation_.find(recommendation_key(iv)); it != by_recommendation_.end()) {
    r.already = it->second;
    r.error = "recommendation '" + iv.recommendation_id() + "' is already approved (" + it->second + ")";
  } else {
    r.error = keep(iv, stop);
    r.published = r.error.empty();
  }
  r.readers = writer_.matched_readers();
  if (r.published) {
    ++counts_.approved;
  } else {
    ++counts_.refused;
    spdlog::warn("approval {} refused: {}", iv.request_id(), r.error);
  }
  return r;
}

void ApprovalKeeper::send_due(const std::atomic<bool>& stop) {
  for (auto& iv : bridge_.due(ApprovalBridge::Clock::now())) bridge_.on_reply(approve(iv, stop));
  std::vector<causal_twin::Intervention> copies;
  copies.swap(copies_);
  for (auto& iv : copies) {
    if (written_.count(iv.request_id()) > 0) continue;
    if (!dds::partitions_allow_group(own_partitions_, iv.asset_group())) {
      ++counts_.not_granted;
      spdlog::warn("approval {} by {} not kept for late readers: twin-web's identity is not granted asset group '{}'",
                   iv.request_id(), iv.approved_by(), iv.asset_group());
      continue;
    }
    const std::string why = keep(iv, stop);
    if (why.empty()) {
      ++counts_.kept;
      spdlog::info("approval {} by {} kept for readers that join later", iv.request_id(), iv.approved_by());
    } else {
      ++counts_.failed;
      spdlog::error("approval {} by {} not kept for late readers: {}", iv.request_id(), iv.approved_by(), why);
    }
  }
}

void ApprovalKeeper::log_summary() const {
  spdlog::info("summary topic={} approved={} refused={} kept={} not_entitled={} not_granted={} failed={} asked={} "
               "answered={}", dds::topics::kIntervention, counts_.approved, counts_.refused, counts_.kept,
               counts_.not_entitled, counts_.not_granted, counts_.failed, bridge_.asked(), bridge_.answered());
}

}  // namespace causal::web
