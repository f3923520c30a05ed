#include "causal/prognosis/time_to_level.hpp"

#include "causal/estimation/normal_quantile.hpp"
#include "causal/io/enum_names.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace causal::prognosis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kGridStart = 1.0 / 60.0;  // one minute: the first grid point after now
constexpr int kGridPoints = 400;           // log-spaced up to the horizon (2.4 % apart at 2000 h)

// Standardised distance of the predicted log level s hours ahead above the threshold.
double standardised(const TrendState& st, const TrendParams& trend, double log_threshold, double s) {
  const Forecast f = forecast(st, trend, s);
  return (f.mean - log_threshold) / std::sqrt(std::max(f.var, 1e-300));
}

double grid_time(int k, double horizon) {
  return kGridStart * std::pow(horizon / kGridStart, static_cast<double>(k) / (kGridPoints - 1));
}

// First t in [0, horizon] with standardised(t) >= z (the p-quantile of T for z = Phi^-1(p)); NaN if none.
double first_time_at_or_above(const TrendState& st, const TrendParams& trend, double log_threshold, double z,
                              double horizon) {
  if (standardised(st, trend, log_threshold, 0.0) >= z) return 0.0;
  double before = 0.0;
  for (int k = 0; k < kGridPoints; ++k) {
    const double t = grid_time(k, horizon);
    if (standardised(st, trend, log_threshold, t) >= z) {
      double lo = before, hi = t;
      for (int i = 0; i < 60 && hi - lo > 1e-9 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (standardised(st, trend, log_threshold, mid) >= z ? hi : lo) = mid;
      }
      return hi;
    }
    before = t;
  }
  return kNaN;
}

// Pessimistic scenario (PrognosisParams::pessimistic_z): level m' = m + z sd(m), slope b' = b + z sd(b) and
// acceleration a' = max(a, 0) + z sd(a) (sds scaled by the calibration's inflation), and the log level's slope
// growing exponentially at the rate lambda = a' / b' that matches a' now: m(s) = m' + b' (exp(lambda s) - 1) / lambda. Why exponential:
// wear whose amplitude grows exponentially (w = c (exp(lambda tau) - 1)) has a log level whose acceleration
// itself grows, faster than any quadratic extrapolation (the "truth earlier than the interval" misses in
// docs/prognosis.md). Returns the first s in (0, horizon] at which this path reaches the threshold, NaN if none.
double pessimistic_time(const TrendState& st, double log_threshold, double z, double horizon) {
  const double b = st.x[1] + z * std::sqrt(std::max(st.inflation * st.p(1, 1), 0.0));
  const double a = std::max(st.x[2], 0.0) + z * std::sqrt(std::max(st.inflation * st.p(2, 2), 0.0));
  const double gap = log_threshold - (st.x[0] + z * std::sqrt(std::max(st.inflation * st.p(0, 0), 0.0)));
  if (gap <= 0.0) return 0.0;
  if (b <= 0.0) return kNaN;
  const double lambda = a / b;
  // Solve m + b (exp(lambda s) - 1) / lambda = L for s; lambda -> 0 is the straight line.
  const double s = lambda * horizon < 1e-9 ? gap / b : std::log1p(lambda * gap / b) / lambda;
  return s <= horizon ? s : kNaN;
}

void unknown(TimeToLevel& out, std::string why) {
  out.known = false;
  out.hours = out.hours_low = out.hours_high = kNaN;
  out.why = std::move(why);
}

void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("PrognosisParams.") + field + " " + what);
}

}  // namespace

const char* to_string(Level level) {
  static constexpr auto kNames = io::enum_names<Level>(
      {{Level::warning, "warning"}, {Level::critical, "critical"}, {Level::end_of_life, "end_of_life"}});
  return kNames.name(level, "?");
}

void PrognosisParams::validate() const {
  trend.validate();
  excess.validate();
  require(history_limit >= 16, "history_limit", "must be >= 16");
  require(trend_fit_limit >= 0, "trend_fit_limit", "must be >= 0");
  require(std::isfinite(end_of_life_ratio) && end_of_life_ratio > 1, "end_of_life_ratio", "must be finite and > 1");
  require(coverage > 0 && coverage < 1, "coverage", "must be in (0, 1)");
  require(std::isfinite(min_trend_z) && min_trend_z >= 0, "min_trend_z", "must be finite and >= 0");
  require(min_points_since_onset >= 2, "min_points_since_onset", "must be >= 2");
  require(std::isfinite(max_horizon_hours) && max_horizon_hours > 1, "max_horizon_hours", "must be finite and > 1");
  require(std::isfinite(max_width_factor) && max_width_factor > 1, "max_width_factor", "must be finite and > 1");
  require(std::isfinite(pessimistic_z) && pessimistic_z >= 0, "pessimistic_z", "must be finite and >= 0");
}

double crossing_probability(const TrendState& s, const TrendParams& trend, double log_threshold, double hours) {
  double best = standardised(s, trend, log_threshold, 0.0);
  for (int k = 0; k < kGridPoints; ++k) {
    const double t = grid_time(k, std::max(hours, kGridStart));
    if (t > hours) break;
    best = std::max(best, standardised(s, trend, log_threshold, t));
  }
  best = std::max(best, standardised(s, trend, log_threshold, hours));
  return 0.5 * std::erfc(-best / std::sqrt(2.0));
}

TimeToLevel time_to_level(const TrendState& s, const TrendParams& trend, double log_threshold,
                          std::uint64_t points_since_onset, const PrognosisParams& params) {
  TimeToLevel out;
  if (!std::isfinite(log_threshold) || !s.x.allFinite() || !s.p.allFinite()) {
    unknown(out, "no trend (no finite level or threshold)");
    return out;
  }
  if (s.x[0] >= log_threshold) {
    out.known = out.reached = true;
    out.hours = out.hours_low = out.hours_high = 0.0;
    return out;
  }
  char buf[200];
  if (points_since_onset < static_cast<std::uint64_t>(params.min_points_since_onset)) {
    std::snprintf(buf, sizeof buf, "too little data since the onset (%llu of %d observations)",
                  static_cast<unsigned long long>(points_since_onset), params.min_points_since_onset);
    unknown(out, buf);
    return out;
  }
  const double slope_z = s.x[1] / std::sqrt(std::max(s.p(1, 1), 1e-300));
  if (slope_z < params.min_trend_z) {
    std::snprintf(buf, sizeof buf, "no significantly rising trend (slope %+.3g %%/h, %.1f sd)",
                  100.0 * std::expm1(s.x[1]), slope_z);
    unknown(out, buf);
    return out;
  }
  const double tail = 0.5 * (1.0 - params.coverage);
  const double h = params.max_horizon_hours;
  const double median = first_time_at_or_above(s, trend, log_threshold, 0.0, h);
  const double low = first_time_at_or_above(s, trend, log_threshold, estimation::normal_quantile(tail), h);
  const double high = first_time_at_or_above(s, trend, log_threshold, estimation::normal_quantile(1.0 - tail), h);
  if (!std::isfinite(median) || !std::isfinite(high)) {
    std::snprintf(buf, sizeof buf, "the %g %% point is beyond the %g h horizon", 100.0 * (1.0 - tail), h);
    unknown(out, buf);
    return out;
  }
  if (high > params.max_width_factor * median) {
    std::snprintf(buf, sizeof buf, "interval too wide (%.3g to %.3g h around %.3g h: more than a factor %g)", low, high,
                  median, params.max_width_factor);
    unknown(out, buf);
    return out;
  }
  out.known = true;
  out.hours = median;
  out.hours_low = low;
  if (params.pessimistic_z > 0) {
    const double early = pessimistic_time(s, log_threshold, params.pessimistic_z, h);
    if (std::isfinite(early) && early < low) out.hours_low = early;
  }
  out.hours_high = high;
  return out;
}

}  // namespace causal::prognosis
