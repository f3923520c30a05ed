// alarm-recommender: operators' alarm actions (alarm_action_desk.hpp) applied, and the AssetStatus of every group
// whose unacknowledged or shelved count changed published again at once (not at its next observation).
#include "recommender_node.hpp"

#include <set>

#include <spdlog/spdlog.h>

namespace causal::recommender {

std::size_t RecommenderNode::poll_alarm_actions() {
  std::set<std::string> changed;
  const std::size_t n = action_desk_.poll(changed, loop_.stop_flag());
  for (auto& alarm : action_desk_.take_health_alarms()) publish_health_alarm(alarm);  // refused writers
  for (const auto& group : changed) {
    causal_twin::AssetStatus msg;
    if (!status_.refresh(group, [this](causal_twin::AssetStatus& s) { action_desk_.fill(s); }, msg)) continue;
    spdlog::info("STATUS {} {}: {} unacknowledged, {} shelved", group, msg.state(), msg.unacknowledged_alarms(),
                 msg.shelved_alarms());
    const dds::WriteResult r = status_writer_.write(msg, loop_.stop_flag());
    if (r == dds::WriteResult::Ok) {
      ++statuses_published_;
    } else if (r != dds::WriteResult::Stopped) {
      ++status_write_failures_;
      spdlog::warn("asset status of '{}' not published after an alarm action", group);
    }
  }
  return n;
}

}  // namespace causal::recommender
