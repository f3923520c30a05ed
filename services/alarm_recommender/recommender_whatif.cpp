// alarm-recommender's what-if requests come from operator identities (twin-web, causal-ask): a request is answered
// only when its writer's grant, as of the writer's first discovery, names the request's asset group
// (dds/writer_grant_check.hpp, the check causal-estimator applies to its inputs). A refused request is answered
// "refused" (its asker is not left waiting), counted (summary, whatif_requests_not_answered_total{reason=
// "not_entitled"}), alarmed once per writer and group (HEALTH group_not_entitled naming the writer's participant)
// and makes the exit code 4.
#include "recommender_node.hpp"

#include "advice_conversions.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <spdlog/spdlog.h>

namespace causal::recommender {

std::size_t RecommenderNode::take_whatif_requests() {
  static metrics::Counter& not_entitled = metrics::process_metrics().counter(
      "whatif_requests_not_answered_total", "What-if requests alarm-recommender refused to answer, by reason",
      {{"reason", "not_entitled"}});
  return whatif_requests_.take_all(
      [&](const causal_twin::WhatIfRequest& r, const eprosima::fastdds::dds::SampleInfo& info) {
        ++whatif_received_;
        if (whatif_grants_.entitled(r.asset_group(), info.sample_identity.writer_guid())) {
          answer(r);
          return;
        }
        ++whatif_not_entitled_;
        not_entitled.inc();
        for (auto& alarm : whatif_grants_.take_alarms()) publish_health_alarm(alarm);
        WhatIfAnswer refused;
        refused.error = "refused: the asker may not ask about asset group '" + r.asset_group() +
                        "' (its grant does not name it, or its partitions changed after discovery)";
        causal_twin::WhatIfReply reply;
        to_whatif_reply(r, refused, reply);
        if (whatif_replies_.write(reply, loop_.stop_flag()) != dds::WriteResult::Ok) {
          spdlog::error("what-if {}: the refusal could not be published (stopping or the writer failed)",
                        r.request_id());
        }
      });
}

void RecommenderNode::publish_health_alarm(causal_twin::Alarm& alarm) {
  const bool cleared = alarm.state() == causal_twin::CLEARED;
  spdlog::log(cleared ? spdlog::level::info : spdlog::level::warn, "HEALTH {} {}: {}", cleared ? "CLEARED" : "RAISED",
              alarm.alarm_id(), alarm.reason());
  action_desk_.on_publish(alarm);
  if (alarms_.write(alarm, loop_.stop_flag()) == dds::WriteResult::Ok) {
    ++alarms_published_;
    open_alarms_.on_published(alarm);
  }
}

void RecommenderNode::log_whatif_summary() const {
  if (whatif_not_entitled_ > 0) {
    spdlog::error("{} what-if requests refused: their writers may not ask about their asset group ({} writer/group "
                  "pairs)", whatif_not_entitled_, whatif_grants_.refused_pairs());
  }
  spdlog::info("summary topic=causal_twin/whatif_request received={} not_entitled={}", whatif_received_,
               whatif_not_entitled_);
}

}  // namespace causal::recommender
