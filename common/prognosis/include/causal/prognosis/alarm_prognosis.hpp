// The prognosis side of alarm-recommender, without DDS: feeds an asset group's ChannelTrends from the
// observations its AlarmEngine judged (with the engine's baselines), and gives, for every channel with an open
// degradation alarm, the time to each level; and for an alarm event, its next level. alarm-recommender and
// causal-prognosis-eval both call exactly these functions.
#pragma once

#include "causal/alarms/alarm_engine.hpp"
#include "causal/prognosis/channel_trends.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace causal::prognosis {

// Healthy measurement std (log units) and log baseline of every channel from the engine; NaN where the
// channel has no baseline (yet).
struct EngineBaselines {
  Eigen::VectorXd log_location, log_scale;
};
EngineBaselines baselines_of(const alarms::AlarmEngine& engine);

// Call after engine.observe(obs). discontinuity: obs.discontinuity, or the engine counted one at this
// observation (a time gap it found itself). Returns the channel values the trends refused.
int observe_for_prognosis(ChannelTrends& trends, const alarms::AlarmEngine& engine, const alarms::Observation& obs,
                          bool discontinuity);

struct ChannelPrognosis {
  int channel = 0;                 // 0-based
  std::string alarm_id;            // the open degradation alarm (the one with the earliest onset)
  std::uint64_t onset_index = 0;
  Level level = Level::warning;
  double ratio = 0.0;              // the level as a multiple of the baseline
  double current_ratio = 0.0;      // filtered level / baseline
  double growth_per_hour = 0.0;    // filtered slope of the log level
  TimeToLevel time;
};

// One entry per level (warning, critical, end of life) for every channel with an open degradation alarm,
// channel order. index: the observation's index (points since onset = index - onset + 1).
std::vector<ChannelPrognosis> open_alarm_prognoses(const ChannelTrends& trends, const alarms::AlarmEngine& engine,
                                                   std::uint64_t index);

// The next level ahead of a degradation event of this severity (advisory -> warning -> critical ->
// end of life) and the time to it; false for a cleared event or another category (no level ahead).
bool next_level_of(const ChannelTrends& trends, const alarms::AlarmEngine& engine, const alarms::AlarmEvent& event,
                   ChannelPrognosis& out);

}  // namespace causal::prognosis
