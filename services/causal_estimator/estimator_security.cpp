// causal-estimator and DDS-Security: authorisation per asset group (a writer may write only the groups its
// signed grant names as partitions: dds/group_partitions.hpp) and the HEALTH alarm before this process's own
// certificate expires. Every refusal is counted (summary, estimator_inputs_not_processed_total{reason=
// "not_entitled"}), logged, alarmed and makes the exit code 4.
#include "estimator_node.hpp"

#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <sstream>

namespace causal::estimator {

bool EstimatorNode::entitled(const std::string& asset_group, const WriterGuid* writer, bool frame) {
  if (writer == nullptr) return true;  // released from the reorder hold: checked when it arrived
  const auto partitions = participant_.directory().writer_partitions(*writer);
  // A writer that announced other partitions after its first discovery is refused from then on, whatever they
  // are: Fast DDS keeps the match of a writer that moves to partitions its grant does not name.
  const auto changed = participant_.directory().writer_partitions_changed(*writer);
  // Discovery reports a writer (with its partitions) before Fast DDS matches it, so every sample's writer is
  // known; one that is not cannot be checked and is refused like a writer without the grant.
  if (!changed && partitions && dds::partitions_allow_group(*partitions, asset_group)) return true;
  (frame ? not_entitled_frames_ : not_entitled_conditions_) += 1;
  not_processed_entitlement_->inc();
  std::ostringstream text;
  text << *writer;
  const std::string who = text.str();
  const std::string participant = participant_.directory().name_of(writer->guidPrefix);
  const auto listed = [](const std::optional<std::vector<std::string>>& names) {
    std::string joined;
    if (names) {
      for (const auto& p : *names) joined += (joined.empty() ? "" : ", ") + (p.empty() ? std::string("''") : p);
    }
    return joined;
  };
  const std::string why =
      changed ? fmt::format("writer {} of participant '{}' changed its partitions after discovery, from [{}] to [{}] "
                            "(refused from then on)", who, participant, listed(partitions), listed(changed))
      : partitions ? fmt::format("writer {} of participant '{}' may write only its partitions [{}]", who, participant,
                                 listed(partitions))
                   : fmt::format("writer {} was never discovered (its grant is unknown)", who);
  const std::uint64_t total = not_entitled_frames_ + not_entitled_conditions_;
  const bool first_of_pair =
      not_entitled_pairs_.size() < 1024 && not_entitled_pairs_.insert(who + "|" + asset_group).second;
  if (!first_of_pair) {
    if (total % 1000 == 0) spdlog::error("{} inputs refused so far: their writers may not write their asset group", total);
    return false;
  }
  spdlog::error("asset group '{}' refused from this writer: {} (issue-identity.sh --groups); its input is refused "
                "(counted, exit 4)", asset_group, why);
  raise_input_alarm(asset_group, "group_not_entitled", causal_twin::CRITICAL, not_entitled_pairs_.size(),
                    static_cast<double>(total), 0.0,
                    "input for asset group '" + asset_group + "' refused: " + why +
                        "; a sensor identity is granted only its own asset groups");
  return false;
}

void EstimatorNode::check_certificate_expiry() {
  const std::int64_t expiry = participant_.certificate_expiry_s();
  if (expiry == 0 || certificate_alarmed_) return;
  const std::int64_t now = io::utc_now_ns();
  const double days_left = (static_cast<double>(expiry) - static_cast<double>(now) / 1e9) / 86400.0;
  if (days_left > kCertificateWarningDays) return;
  certificate_alarmed_ = true;
  causal_twin::Alarm alarm;
  alarm.alarm_id(fmt::format("estimator/security/certificate_expiring/t{}", now / 1000000000));
  alarm.asset_group("");
  alarm.kind("certificate_expiring");
  alarm.category("health");
  alarm.severity(days_left <= 1.0 ? causal_twin::CRITICAL : causal_twin::WARNING);
  alarm.state(causal_twin::RAISED);
  alarm.raised_time_ns(now);
  alarm.score(days_left);
  alarm.threshold(kCertificateWarningDays);
  alarm.reason(fmt::format("this causal-estimator's DDS-Security certificate expires in {:.1f} days ({}): issue a new "
                           "one (deploy/security/issue-identity.sh) and restart it before then, or it can no longer "
                           "join the bus",
                           days_left, participant_.security_note()));
  publish_health_alarm(std::move(alarm));
}

}  // namespace causal::estimator
