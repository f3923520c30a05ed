#include "recommender_node.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

namespace causal::recommender {

namespace {
using Clock = std::chrono::steady_clock;
}

RecommenderNode::RecommenderNode(RecommenderOptions options, RecommenderParams params)
    : options_(std::move(options)),
      params_(std::move(params)),
      participant_(dds::to_dds_settings(options_.dds, "alarm-recommender")),
      factors_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsReader),
      conditions_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader),
      alarms_(participant_, dds::topics::kAlarm, dds::profiles::kAlarmWriter) {
  loop_.attach(factors_.get());
  loop_.attach(conditions_.get());
}

int RecommenderNode::run() {
  spdlog::info("alarm-recommender on domain {}, waiting for causal factors", participant_.domain_id());
  const auto started = Clock::now();
  auto last_data = started;
  bool any_data = false;
  std::vector<AssembledObservation> ready;
  while (loop_.wait(std::chrono::milliseconds(200))) {
    ready.clear();
    std::size_t n = conditions_.take_all([&](const causal_twin::ConditionVector& c, const auto&) {
      if (!dds::validate_condition_vector(c).empty()) {
        ++invalid_msgs_;
        return;
      }
      assembler_.add_condition(c.asset_group(), c.feature(), c.time_ns(), dds::values_of(c), ready);
    });
    n += factors_.take_all([&](const causal_twin::CausalFactors& f, const auto&) {
      if (const auto problem = dds::validate_causal_factors(f); !problem.empty()) {
        ++invalid_msgs_;
        spdlog::warn("causal factors from '{}' refused: {}", f.asset_group(), problem);
        return;
      }
      assembler_.add_factors(dds::from_causal_factors(f), ready);
    });
    handle(ready);
    const auto now = Clock::now();
    if (n > 0) {
      last_data = now;
      any_data = true;
    }
    if (options_.idle_exit_s > 0 && any_data &&
        std::chrono::duration<double>(now - last_data).count() > options_.idle_exit_s) {
      spdlog::info("no data for {:.1f} s: finishing", options_.idle_exit_s);
      break;
    }
    if (options_.max_runtime_s > 0 && std::chrono::duration<double>(now - started).count() > options_.max_runtime_s) {
      spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
      break;
    }
  }
  ready.clear();
  assembler_.flush(ready);
  handle(ready);
  for (const auto& [key, st] : engines_) {
    const auto active = st.engine->active_alarms();
    spdlog::info("asset '{}' {} level: {} observations, {} alarms raised, {} still active", key.first,
                 key.second == causal_twin::SAMPLE_LEVEL ? "sample" : "condition", st.engine->observations_seen(),
                 st.raised, active.size());
  }
  if (invalid_msgs_ > 0) spdlog::warn("{} malformed messages refused", invalid_msgs_);
  if (assembler_.dropped_incomplete() > 0) {
    spdlog::warn("{} factor sets never completed (lost outcome messages)", assembler_.dropped_incomplete());
  }
  if (!alarms_.wait_for_acknowledgments(std::chrono::seconds(10))) {
    spdlog::warn("not every alarm was acknowledged within 10 s");
  }
  spdlog::info("{} alarm messages published", alarms_published_);
  return 0;
}

void RecommenderNode::handle(std::vector<AssembledObservation>& ready) {
  for (auto& a : ready) observe(a);
}

void RecommenderNode::observe(AssembledObservation& a) {
  const bool sample = a.time_scale == causal_twin::SAMPLE_LEVEL;
  if (sample ? !params_.sample_enabled : !params_.condition_enabled) return;
  auto key = std::make_pair(a.asset_group, static_cast<int>(a.time_scale));
  auto it = engines_.find(key);
  if (it == engines_.end()) {
    EngineState st;
    const alarms::AlarmParams p =
        sample ? alarms::AlarmParams::sample_level(params_.sample_baseline_publications) : params_.condition;
    st.engine = std::make_unique<alarms::AlarmEngine>(a.asset_group, a.channel_names, a.factor_names, p);
    st.channel_names = a.channel_names;
    it = engines_.emplace(key, std::move(st)).first;
    spdlog::info("asset '{}' {} level: learning the baseline from the first {} observations", a.asset_group,
                 sample ? "sample" : "condition", p.warmup_observations + p.baseline_observations);
  }
  EngineState& st = it->second;
  for (const auto& e : st.engine->observe(a.observation)) {
    if (e.state == alarms::AlarmState::Raised) ++st.raised;
    publish_event(a, e);
  }
  if (!st.baseline_logged && st.engine->baseline_ready()) {
    st.baseline_logged = true;
    spdlog::info("asset '{}' {} level: baseline learned, monitoring from observation {}", a.asset_group,
                 sample ? "sample" : "condition", a.observation.index);
  }
}

void RecommenderNode::publish_event(const AssembledObservation& a, const alarms::AlarmEvent& e) {
  dds::to_alarm(a.asset_group, a.channel_names, e, alarm_msg_);
  if (alarms_.write(alarm_msg_, loop_.stop_flag()) == dds::WriteResult::Ok) ++alarms_published_;
  const auto level = e.severity == alarms::Severity::Critical  ? spdlog::level::err
                     : e.severity == alarms::Severity::Warning ? spdlog::level::warn
                                                               : spdlog::level::info;
  spdlog::log(level, "ALARM {} {} [{} {}] {}: {}", alarms::to_string(e.state), e.alarm_id, alarms::to_string(e.severity),
              a.time_scale == causal_twin::SAMPLE_LEVEL ? "sample-level" : "condition-level",
              alarm_msg_.channel_name(), e.reason);
}

}  // namespace causal::recommender
