// causal-estimator, HEALTH alarms it raises about itself: a reader that keeps the output waiting (the output
// watchdog), this process's certificate before it expires, and silent or lost inputs (HealthWatch).
#include "estimator_publishing.hpp"

#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

void EstimatorPublisher::watch_output() {
  // A reader that does not acknowledge (frozen, or far behind) makes the drain thread wait; the filters go on
  // (the outbound queue). Make it visible: a HEALTH alarm while a write has waited longer than stuck_after_s.
  const double blocked = std::chrono::duration<double>(outbound_.blocked_for()).count();
  if (!stuck_alarm_ && blocked > options_.stuck_after_s && !standing_by_) {
    const std::int64_t now_ns = io::utc_now_ns();
    causal_twin::Alarm a;
    a.alarm_id("causal-estimator/output/reader_not_keeping_up/t" + std::to_string(now_ns / 1000000000));
    a.kind("reader_not_keeping_up");
    a.category("health");
    a.severity(causal_twin::WARNING);
    a.state(causal_twin::RAISED);
    a.raised_time_ns(now_ns);
    a.score(blocked);
    a.threshold(options_.stuck_after_s);
    a.reason(fmt::format("a reader of the estimator's output has not acknowledged for {:.1f} s (readers: {}); its "
                         "delivery waits, up to the reader's 5 s lease, the filters go on and {} messages are queued",
                         blocked, fmt::join(participant_.directory().reader_names(factors_.sets() ? dds::topics::kCausalFactorSets
                                                                                            : dds::topics::kCausalFactors),
                                   ", "),
                         outbound_.size()));
    stuck_alarm_ = a;
  } else if (stuck_alarm_ && blocked == 0.0) {
    stuck_alarm_->state(causal_twin::CLEARED);
    stuck_alarm_->cleared_time_ns(io::utc_now_ns());
    stuck_alarm_->reason("every reader acknowledges again");
  } else {
    return;
  }
  const bool cleared = stuck_alarm_->state() == causal_twin::CLEARED;
  spdlog::log(cleared ? spdlog::level::info : spdlog::level::warn, "HEALTH {} {}: {}", cleared ? "CLEARED" : "RAISED",
              stuck_alarm_->alarm_id(), stuck_alarm_->reason());
  // Written directly, not through the (blocked) queue: the alarm writer keeps the last value per id and never waits.
  if (quality_alarms_.write(*stuck_alarm_, stop_) != dds::WriteResult::Ok)
    spdlog::error("HEALTH {} could not be published (stopping or the alarm writer failed)", stuck_alarm_->alarm_id());
  if (cleared) stuck_alarm_.reset();
}

void EstimatorPublisher::publish_health(dds::HealthWatch& health) {
  watch_output();
  check_certificate_expiry();
  health.check(participant_.directory());
  for (auto& alarm : health.take_alarms()) {
    const bool cleared = alarm.state() == causal_twin::CLEARED;
    spdlog::log(cleared ? spdlog::level::info : spdlog::level::warn, "HEALTH {} {}: {}", cleared ? "CLEARED" : "RAISED",
                alarm.alarm_id(), alarm.reason());
    if (standing_by_) continue;  // the primary publishes them (as with the data-quality alarms)
    push_alarm("alarm/health", std::move(alarm));
  }
}

void EstimatorPublisher::check_certificate_expiry() {
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
