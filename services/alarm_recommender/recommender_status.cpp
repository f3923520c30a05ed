// alarm-recommender: the AssetStatus line of a group (asset_status.hpp), published on causal_twin/asset_status when
// it changes (transient-local, last value per group: a view that joins later gets every group's state).
#include "recommender_node.hpp"

#include "prognosis_conversions.hpp"

#include <spdlog/spdlog.h>

namespace causal::recommender {

std::string RecommenderNode::status_prognosis(const EngineState& st, const alarms::AlarmEvent& worst) const {
  if (!params_.prognosis_enabled || !st.trends) return "";
  // The root cause's own condition-level alarm when it has one (the asset to act on), else the worst alarm's
  // channel; the prognosis trends follow the condition level only.
  const int channel = worst.root_cause_channel >= 0 ? worst.root_cause_channel : worst.channel;
  const alarms::AlarmEvent* chosen = nullptr;
  const auto active = st.engine->active_alarms();
  for (const auto& e : active) {
    if (e.category != alarms::category::kDegradation || e.channel != channel) continue;
    if (chosen == nullptr || e.severity > chosen->severity) chosen = &e;
  }
  if (chosen == nullptr) {
    for (const auto& e : active) {
      if (e.alarm_id == worst.alarm_id) chosen = &e;
    }
  }
  prognosis::ChannelPrognosis p;
  if (chosen == nullptr || !prognosis::next_level_of(*st.trends, *st.engine, *chosen, p)) return "unknown";
  const auto& names = st.channel_names;
  const std::string name = p.channel >= 0 && static_cast<std::size_t>(p.channel) < names.size()
                               ? names[static_cast<std::size_t>(p.channel)] : std::to_string(p.channel + 1);
  return status_prognosis_text(name, p, st.trends->trend(p.channel).state().time_ns);
}

void RecommenderNode::publish_status(const AssembledObservation& a, bool stopped_now) {
  StatusInput in;
  const auto condition = engines_.find({a.asset_group, static_cast<int>(causal_twin::CONDITION_LEVEL)});
  const auto sample = engines_.find({a.asset_group, static_cast<int>(causal_twin::SAMPLE_LEVEL)});
  in.condition = condition != engines_.end() ? condition->second.engine.get() : nullptr;
  in.sample = sample != engines_.end() ? sample->second.engine.get() : nullptr;
  const bool from_sample = a.time_scale == causal_twin::SAMPLE_LEVEL;
  // The operating state and the learning count come from the condition level when it runs (one observation per
  // snapshot); the sample level speaks for them only when it runs alone.
  if (from_sample && in.condition != nullptr) {
    const auto& last = status_last_stopped_[a.asset_group];
    in.stopped_now = last;
  } else {
    in.stopped_now = stopped_now;
    status_last_stopped_[a.asset_group] = stopped_now;
  }
  in.index = a.observation.index;
  in.time_ns = a.observation.time_ns;
  if (condition != engines_.end()) {
    const EngineState& st = condition->second;
    in.prognosis = [this, &st](const alarms::AlarmEvent& worst) { return status_prognosis(st, worst); };
  }
  in.management = [this](causal_twin::AssetStatus& s) { action_desk_.fill(s); };
  causal_twin::AssetStatus msg;
  if (!status_.update(a.asset_group, in, msg)) return;
  const bool learning = msg.state() == "learning";
  // Learning advances at every observation: logged at debug, the other states when they change.
  spdlog::log(learning ? spdlog::level::debug : spdlog::level::info, "STATUS {} {}: {}", a.asset_group, msg.state(),
              msg.text());
  const dds::WriteResult r = status_writer_.write(msg, loop_.stop_flag());
  if (r == dds::WriteResult::Ok) {
    ++statuses_published_;
  } else if (r != dds::WriteResult::Stopped && status_write_failures_++ % 100 == 0) {
    // A reader that stays behind past the give-up time (not a stop): counted, logged and in the exit code.
    spdlog::warn("asset status of '{}' not published ({} failures so far)", a.asset_group, status_write_failures_);
  }
}

}  // namespace causal::recommender
