#include "prognosis_conformal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace causal::prognosis_eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The conformal rank of p in sorted errors: the ceil((n + 1) p)-th smallest, clamped (a finite-sample valid
// upper quantile).
double quantile(const std::vector<double>& sorted, double p) {
  const double n = static_cast<double>(sorted.size());
  auto k = static_cast<std::ptrdiff_t>(std::ceil((n + 1.0) * p)) - 1;
  k = std::clamp<std::ptrdiff_t>(k, 0, static_cast<std::ptrdiff_t>(sorted.size()) - 1);
  return sorted[static_cast<std::size_t>(k)];
}

}  // namespace

ConformalLevel::ConformalLevel(const std::vector<double>& t, const std::vector<double>& y, int min_errors)
    : min_errors_(min_errors) {
  if (t.empty()) return;
  // blocks counted back from now, so the last median is the level of the last hour
  const double now = t.back();
  const auto blocks = static_cast<std::size_t>(std::floor(now)) + 1;
  std::vector<std::vector<std::pair<double, double>>> in(blocks);  // (time, level) per block
  for (std::size_t i = 0; i < t.size(); ++i) {
    // 1e-9 h: a time on a block's edge (i / 6 h in floating point) stays in the block it is on
    const auto back = static_cast<std::size_t>(std::floor(now - t[i] + 1e-9));
    if (back < blocks && std::isfinite(y[i])) in[blocks - 1 - back].push_back({t[i], y[i]});
  }
  for (auto& b : in) {
    if (b.empty()) continue;  // a recording gap: no block (the horizons count blocks, the rates use times)
    std::vector<double> times, levels;
    for (const auto& [ti, yi] : b) {
      times.push_back(ti);
      levels.push_back(yi);
    }
    const auto mid = static_cast<std::ptrdiff_t>(b.size() / 2);
    std::nth_element(times.begin(), times.begin() + mid, times.end());
    std::nth_element(levels.begin(), levels.begin() + mid, levels.end());
    time_.push_back(times[static_cast<std::size_t>(mid)]);
    median_.push_back(levels[static_cast<std::size_t>(mid)]);
  }
  for (std::size_t k = 0; k < median_.size(); ++k)
    rate_.push_back(k == 0 ? kNaN : (median_[k] - median_[0]) / (time_[k] - time_[0]));
  // the horizons count from the last block's median time (its level's time), the answers from now
  if (!time_.empty()) offset_ = now - time_.back();
}

Prediction ConformalLevel::time_to(double log_ratio, double coverage) const {
  Prediction p;
  p.hours = p.low = p.high = kNaN;
  const std::size_t n = median_.size();
  if (n < 3) {
    p.why = "fewer than 3 hours since the onset";
    return p;
  }
  const double m = median_.back(), v = rate_.back();
  if (m >= log_ratio) {
    p.known = p.reached = true;
    p.hours = p.low = p.high = 0;
    return p;
  }
  if (!(v > 0)) {
    p.why = "the mean rate since the onset is not rising";
    return p;
  }
  const double a = 0.5 * (1.0 - coverage);
  double prev_lo = m, prev_mid = m, prev_hi = m;
  bool have_low = false, have_mid = false;
  std::vector<double> err;
  for (std::size_t h = 1; h < n; ++h) {
    err.clear();
    for (std::size_t k = 1; k + h < n; ++k)
      err.push_back(median_[k + h] - (median_[k] + rate_[k] * (time_[k + h] - time_[k])));
    if (err.size() < static_cast<std::size_t>(min_errors_)) break;
    std::sort(err.begin(), err.end());
    const double base = m + v * static_cast<double>(h);
    const double lo = base + quantile(err, a), mid = base + quantile(err, 0.5), hi = base + quantile(err, 1.0 - a);
    auto cross = [&](double before, double after) {  // linear in the hour between the bands
      const double f = after > before ? (log_ratio - before) / (after - before) : 1.0;
      return static_cast<double>(h) - 1.0 + std::clamp(f, 0.0, 1.0);
    };
    if (!have_low && hi >= log_ratio) { p.low = cross(prev_hi, hi); have_low = true; }
    if (!have_mid && mid >= log_ratio) { p.hours = cross(prev_mid, mid); have_mid = true; }
    if (lo >= log_ratio) {
      p.high = cross(prev_lo, lo);
      p.known = have_low && have_mid;
      if (!p.known) p.why = "bands not monotone";
      p.low = std::max(0.0, p.low - offset_);
      p.hours = std::max(0.0, p.hours - offset_);
      p.high = std::max(0.0, p.high - offset_);
      return p;
    }
    prev_lo = lo;
    prev_mid = mid;
    prev_hi = hi;
  }
  p.why = "the lower band does not reach the level within the horizons on record";
  return p;
}

}  // namespace causal::prognosis_eval
