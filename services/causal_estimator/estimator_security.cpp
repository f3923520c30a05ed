// causal-estimator and DDS-Security: authorisation per asset group (a writer may write only the groups its
// signed grant names as partitions: dds/group_partitions.hpp) and the HEALTH alarm before this process's own
// certificate expires. The grant check is the one every reader of outside input shares (dds/writer_grant_check.hpp).
// Every refusal is counted (summary, estimator_inputs_not_processed_total{reason="not_entitled"}), logged, alarmed
// and makes the exit code 4.
#include "estimator_node.hpp"

#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <sstream>

namespace causal::estimator {

bool EstimatorNode::entitled(const std::string& asset_group, const WriterGuid* writer, bool frame) {
  if (writer == nullptr) return true;  // released from the reorder hold: checked when it arrived
  if (grants_.entitled(asset_group, *writer)) return true;
  (frame ? not_entitled_frames_ : not_entitled_conditions_) += 1;
  not_processed_entitlement_->inc();
  for (auto& alarm : grants_.take_alarms()) publish_health_alarm(std::move(alarm));
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
