#include "causal/prognosis/channel_trends.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/prognosis/excess_growth.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace causal::prognosis {

namespace {
constexpr const char* kTag = "prognosis_channel_trends";
constexpr std::uint32_t kVersion = 3;  // 2: the trends carry their forecast calibration; 3: and the level history
}  // namespace

ChannelTrends::ChannelTrends(int channels, PrognosisParams params) : params_(params) {
  params_.validate();
  if (channels < 1) throw std::invalid_argument("ChannelTrends needs at least one channel");
  trends_.assign(static_cast<std::size_t>(channels), DegradationTrend(params_.trend));
  history_.assign(static_cast<std::size_t>(channels), {});
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
    const auto c = static_cast<std::size_t>(k);
    if (!trends_[c].observe(time_ns, log_levels[k], noise_std[k], discontinuity)) {
      ++refused;
      continue;
    }
    history_[c].push_back({time_ns, log_levels[k]});
    if (history_[c].size() > params_.history_limit) history_[c].pop_front();
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

TimeToLevel ChannelTrends::time_to(int channel, double baseline_log, double ratio, std::uint64_t points_since_onset,
                                   std::int64_t onset_time_ns, double noise_std) const {
  const DegradationTrend& t = trend(channel);
  if (!t.started()) {
    TimeToLevel out;
    out.hours = out.hours_low = out.hours_high = std::numeric_limits<double>::quiet_NaN();
    out.why = "no trend yet (baseline not learned)";
    return out;
  }
  const TimeToLevel local =
      time_to_level(t.state(), t.params(), baseline_log + std::log(ratio), points_since_onset, params_);
  // The local trend answers while its own recent forecasts fit it; where they do not, it has no say.
  const bool fits = t.state().inflation <= params_.trend_fit_limit;
  if (fits && (local.known || !params_.long_run_fills_unknown)) return local;
  // The long-run model: the log excess over the reference since the onset, hours from the onset.
  std::vector<double> hours, excess;
  for (const Point& p : history(channel)) {
    if (p.time_ns < onset_time_ns) continue;
    hours.push_back(static_cast<double>(p.time_ns - onset_time_ns) / 3.6e12);
    excess.push_back(p.log_level - baseline_log);
  }
  bool too_little_data = false;
  TimeToLevel growth = excess_growth_time_to(hours, excess, noise_std, std::log(ratio), params_, &too_little_data);
  if (growth.known) return growth;
  if (fits || too_little_data) {  // nothing else to go by: the local trend, as it is
    TimeToLevel out = local;
    if (!out.known) out.why += "; long-run growth: " + growth.why;
    return out;
  }
  char buf[120];
  std::snprintf(buf, sizeof buf, "the local trend misses its own forecasts (%.3g x their variance); long-run growth: ",
                t.state().inflation);
  growth.why = buf + growth.why;
  return growth;
}

void ChannelTrends::save(estimation::StateWriter& out) const {
  out.begin(kTag, kVersion);
  out.put(params_.end_of_life_ratio);
  out.put(static_cast<std::uint64_t>(trends_.size()));
  for (const auto& t : trends_) t.save(out);
  out.put(params_.history_limit);
  for (const auto& h : history_) {
    out.put(static_cast<std::uint64_t>(h.size()));
    for (const Point& p : h) {
      out.put(p.time_ns);
      out.put(p.log_level);
    }
  }
  out.put(refused_);
}

ChannelTrends ChannelTrends::restore(estimation::StateReader& in, int channels, const PrognosisParams& params) {
  in.expect(kTag, kVersion);
  const double eol = in.get<double>();
  if (eol != params.end_of_life_ratio) throw estimation::StateError("the trends were written with another end_of_life_ratio");
  const auto n = in.get<std::uint64_t>();
  if (n != static_cast<std::uint64_t>(channels)) {
    throw estimation::StateError("the trends were written for " + std::to_string(n) + " channels, not " +
                             std::to_string(channels));
  }
  ChannelTrends out(channels, params);
  for (auto& t : out.trends_) t = DegradationTrend::restore(in, params.trend);
  if (in.get<std::uint64_t>() != params.history_limit)
    throw estimation::StateError("the trends were written with another history_limit");
  for (auto& h : out.history_) {
    const auto size = in.get<std::uint64_t>();
    if (size > params.history_limit) throw estimation::StateError("the trends' level history is longer than history_limit");
    for (std::uint64_t i = 0; i < size; ++i) {
      const auto time_ns = in.get<std::int64_t>();
      h.push_back({time_ns, in.get<double>()});
    }
  }
  out.refused_ = in.get<std::uint64_t>();
  return out;
}

}  // namespace causal::prognosis
