// The degradation trends of one asset group's G channels, observed once per snapshot, as the services and
// the evaluation tool keep them (the same code path): each channel's trend starts once its healthy baseline
// scale is known, and a prognosis for a level is the time until the log level reaches
// baseline_log + log(ratio), with the baseline as the alarm engine has it at that moment (so a re-baselined
// operating change moves the thresholds with the level).
#pragma once

#include "causal/prognosis/degradation_trend.hpp"
#include "causal/prognosis/time_to_level.hpp"

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <vector>

namespace causal::prognosis {

class ChannelTrends {
 public:
  ChannelTrends(int channels, PrognosisParams params);

  // One snapshot. log_levels: G log features (NaN: no value now, skipped); noise_std: G healthy measurement
  // std of the log feature, NaN for a channel without a baseline yet (its trend does not run). Returns the
  // number of channel values refused (non-finite level with a finite noise, or time not increasing).
  int observe(std::int64_t time_ns, const Eigen::VectorXd& log_levels, const Eigen::VectorXd& noise_std,
              bool discontinuity);

  int channels() const { return static_cast<int>(trends_.size()); }
  const DegradationTrend& trend(int channel) const { return trends_.at(static_cast<std::size_t>(channel)); }
  const PrognosisParams& params() const { return params_; }
  // Ratio of a level: warning_ratio / critical_ratio are the alarm engine's, end of life is ours.
  double ratio(Level level, double warning_ratio, double critical_ratio) const;
  // Time until channel's level reaches ratio x exp(baseline_log); unknown when the trend has not started.
  // onset_time_ns: the degradation alarm's onset; noise_std: the channel's healthy log sd. The forecast is the
  // excess-growth model's (excess_growth.hpp) on the history since the onset where it answers, else the
  // trend's (time_to_level.hpp) when PrognosisParams::excess_fallback_to_trend, else unknown with its reason.
  TimeToLevel time_to(int channel, double baseline_log, double ratio, std::uint64_t points_since_onset,
                      std::int64_t onset_time_ns, double noise_std) const;
  // The log levels the trend accepted, the last PrognosisParams::history_limit of them.
  struct Point {
    std::int64_t time_ns;
    double log_level;
  };
  const std::deque<Point>& history(int channel) const { return history_.at(static_cast<std::size_t>(channel)); }
  std::uint64_t refused() const { return refused_; }

  void save(estimation::StateWriter& out) const;
  // Throws estimation::StateError on a truncated or foreign section or another channel count.
  static ChannelTrends restore(estimation::StateReader& in, int channels, const PrognosisParams& params);

 private:
  PrognosisParams params_;
  std::vector<DegradationTrend> trends_;
  std::vector<std::deque<Point>> history_;
  std::uint64_t refused_ = 0;
};

}  // namespace causal::prognosis
