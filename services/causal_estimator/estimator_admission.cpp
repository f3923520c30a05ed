// causal-estimator, admission of input: the quota on new asset groups (group_quota.hpp) and inputs whose indices
// were processed already (a resend, or new data under old numbers). Nothing here is silent: every input not
// processed is counted (summary, estimator_inputs_not_processed_total{reason}), refusals are logged, alarmed and
// make the exit code 4.
#include "estimator_node.hpp"

#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <sstream>

namespace causal::estimator {

bool EstimatorNode::admitted(const std::string& asset_group, const WriterGuid* writer) {
  std::string who;
  if (writer != nullptr) {
    std::ostringstream text;
    text << *writer;
    who = text.str();
  }
  const auto verdict = quota_.admit(asset_group, who);
  if (verdict == GroupQuota::Verdict::Known || verdict == GroupQuota::Verdict::Admitted) return true;
  not_processed_quota_->inc();
  const auto& limits = quota_.limits();
  const std::string why =
      verdict == GroupQuota::Verdict::OverTotal
          ? fmt::format("this estimator already serves {} asset groups (--max-groups {})", quota_.groups(),
                        limits.max_groups)
          : fmt::format("writer {} already opened {} asset groups (--max-groups-per-writer {})", who,
                        quota_.groups_of(who), limits.max_groups_per_writer);
  if (!quota_alarmed_writers_.insert(who).second) return false;  // counted; one alarm and error line per writer
  spdlog::error("asset group '{}' refused: {}; its input and further new groups of this writer are refused "
                "(counted, exit 4)", asset_group, why);
  raise_input_alarm(asset_group, "asset_group_quota", causal_twin::WARNING, quota_alarmed_writers_.size(),
                    static_cast<double>(quota_.groups()),
                    static_cast<double>(verdict == GroupQuota::Verdict::OverTotal ? limits.max_groups
                                                                                 : limits.max_groups_per_writer),
                    "new asset group '" + asset_group + "' refused: " + why +
                        "; a source that names ever new groups would exhaust memory and checkpoint files");
  return false;
}

void EstimatorNode::raise_input_alarm(const std::string& asset_group, const std::string& kind,
                                      causal_twin::Severity severity, std::size_t serial, double score,
                                      double threshold, const std::string& reason) {
  causal_twin::Alarm alarm;
  const std::int64_t now = io::utc_now_ns();
  // Wall-clock time and a per-kind serial: a refusal has no source index of its own.
  alarm.alarm_id(fmt::format("{}/input/{}/t{}.{}", asset_group, kind, now / 1000000000, serial));
  alarm.asset_group(asset_group);
  alarm.kind(kind);
  alarm.category("health");
  alarm.severity(severity);
  alarm.state(causal_twin::RAISED);
  alarm.raised_time_ns(now);
  alarm.score(score);
  alarm.threshold(threshold);
  alarm.reason(reason);
  publish_health_alarm(std::move(alarm));
}

void EstimatorNode::publish_health_alarm(causal_twin::Alarm alarm) {
  spdlog::warn("HEALTH RAISED {}: {}", alarm.alarm_id(), alarm.reason());
  if (standing_by_) return;  // the active estimator raises it
  auto msg = std::make_shared<causal_twin::Alarm>(std::move(alarm));
  outbound_.push("alarm/health", dds::OutboundQueue::Class::Essential,
                 [this, msg](const std::atomic<bool>& s) { return quality_alarms_.write(*msg, s); }, loop_.stop_flag());
}

void EstimatorNode::not_again(const std::string& name, Asset& a, std::uint64_t snapshot, std::int64_t time_ns,
                              const std::string& what) {
  // A resend (a restarted replay, the transient-local history) carries its old times; new data is later than
  // the last input fed. Without a known last time (a checkpoint from before it was kept) it counts as a resend.
  if (a.last_time_ns == INT64_MIN || time_ns <= a.last_time_ns) {
    ++a.skipped;
    not_processed_already_->inc();
    return;
  }
  ++a.renumbered;
  not_processed_renumbered_->inc();
  const std::string problem =
      fmt::format("the source's numbering went back: {} of snapshot {} was processed already, but its data time {} is "
                  "after the last input processed ({}): a source that restarted its numbering (sensor-ingest keeps it "
                  "with --state-dir); such input is refused, not taken for a resend",
                  what, snapshot, io::format_utc(time_ns), io::format_utc(a.last_time_ns));
  if (a.renumbered == 1) spdlog::error("asset '{}': {}", name, problem);
  report_refusal(name, snapshot, time_ns, problem);
}

}  // namespace causal::estimator
