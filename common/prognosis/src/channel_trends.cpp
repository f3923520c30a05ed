#include "causal/prognosis/channel_trends.hpp"

#include "causal/estimation/state_archive.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::prognosis {

namespace {
constexpr const char* kTag = "prognosis_channel_trends";
constexpr std::uint32_t kVersion = 2;  // 2: the trends carry their forecast calibration
}  // namespace

ChannelTrends::ChannelTrends(int channels, PrognosisParams params) : params_(params) {
  params_.validate();
  if (channels < 1) throw std::invalid_argument("ChannelTrends needs at least one channel");
  trends_.assign(static_cast<std::size_t>(channels), DegradationTrend(params_.trend));
}

int ChannelTrends::observe(std::int64_t time_ns, const Eigen::VectorXd& log_levels, const Eigen::VectorXd& noise_std,
                           bool discontinuity) {
  if (log_levels.size() != channels() || noise_std.size() != channels()) {
    throw std::invalid_argument("ChannelTrends::observe: " + std::to_string(channels()) + " channels expected");
  }
  int refused = 0;
  for (int k = 0; k < channels(); ++k) {
    if (!std::isfinite(noise_std[k])) continue;  // no baseline yet: the trend does not run
    if (std::isnan(log_levels[k])) continue;  // no value now (NaN by contract); +-inf is refused below
    if (!trends_[static_cast<std::size_t>(k)].observe(time_ns, log_levels[k], noise_std[k], discontinuity)) ++refused;
  }
  refused_ += static_cast<std::uint64_t>(refused);
  return refused;
}

double ChannelTrends::ratio(Level level, double warning_ratio, double critical_ratio) const {
  switch (level) {
    case Level::warning: return warning_ratio;
    case Level::critical: return critical_ratio;
    case Level::end_of_life: return params_.end_of_life_ratio;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

TimeToLevel ChannelTrends::time_to(int channel, double baseline_log, double ratio, std::uint64_t points_since_onset) const {
  const DegradationTrend& t = trend(channel);
  if (!t.started()) {
    TimeToLevel out;
    out.hours = out.hours_low = out.hours_high = std::numeric_limits<double>::quiet_NaN();
    out.why = "no trend yet (baseline not learned)";
    return out;
  }
  return time_to_level(t.state(), t.params(), baseline_log + std::log(ratio), points_since_onset, params_);
}

void ChannelTrends::save(causal::StateWriter& out) const {
  out.begin(kTag, kVersion);
  out.put(params_.end_of_life_ratio);
  out.put(static_cast<std::uint64_t>(trends_.size()));
  for (const auto& t : trends_) t.save(out);
  out.put(refused_);
}

ChannelTrends ChannelTrends::restore(causal::StateReader& in, int channels, const PrognosisParams& params) {
  in.expect(kTag, kVersion);
  const double eol = in.get<double>();
  if (eol != params.end_of_life_ratio) throw causal::StateError("the trends were written with another end_of_life_ratio");
  const auto n = in.get<std::uint64_t>();
  if (n != static_cast<std::uint64_t>(channels)) {
    throw causal::StateError("the trends were written for " + std::to_string(n) + " channels, not " +
                             std::to_string(channels));
  }
  ChannelTrends out(channels, params);
  for (auto& t : out.trends_) t = DegradationTrend::restore(in, params.trend);
  out.refused_ = in.get<std::uint64_t>();
  return out;
}

}  // namespace causal::prognosis
