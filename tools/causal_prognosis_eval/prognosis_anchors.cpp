#include "prognosis_anchors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace causal::prognosis_eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What every anchor answers before its fit is asked (hours unknown until then): true when that is the answer,
// because there are too few points, the level is already reached (0 h) or the fit does not rise (`not_rising`).
bool answered_without_fit(bool fitted, bool reached, bool rising, const char* not_rising, Prediction& p) {
  p.hours = p.low = p.high = kNaN;
  if (!fitted) {
    p.why = "too few points";
    return true;
  }
  if (reached) {
    p.known = p.reached = true;
    p.hours = p.low = p.high = 0;
    return true;
  }
  if (!rising) {
    p.why = not_rising;
    return true;
  }
  return false;
}

double median_in_place(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Theil-Sen slope and the fitted level at t_now (median of the residuals y - slope t) of the points idx.
bool theil_sen(const std::vector<double>& t, const std::vector<double>& y, const std::vector<std::size_t>& idx,
               double t_now, std::vector<double>& scratch, double& slope, double& now) {
  scratch.clear();
  for (std::size_t i = 0; i < idx.size(); ++i)
    for (std::size_t j = i + 1; j < idx.size(); ++j) {
      const double dt = t[idx[j]] - t[idx[i]];
      if (dt != 0.0) scratch.push_back((y[idx[j]] - y[idx[i]]) / dt);
    }
  if (scratch.size() < 3) return false;
  slope = median_in_place(scratch);
  scratch.clear();
  for (std::size_t i : idx) scratch.push_back(y[i] - slope * t[i]);
  now = median_in_place(scratch) + slope * t_now;
  return true;
}

// Upper-tail log Phi(-z) for z >= 0 without underflow (Mills ratio beyond z = 25).
double log_normal_tail(double z) {
  if (z < 25.0) return std::log(0.5 * std::erfc(z / std::sqrt(2.0)));
  return -0.5 * z * z - std::log(z * std::sqrt(2.0 * M_PI));
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

}  // namespace

TheilSenBootstrap::TheilSenBootstrap(const std::vector<double>& t, const std::vector<double>& y, int draws,
                                     std::uint64_t seed, int max_points) {
  const std::size_t n = t.size();
  if (n < 3) return;
  std::vector<std::size_t> idx;
  const std::size_t m = std::min<std::size_t>(n, static_cast<std::size_t>(max_points));
  for (std::size_t k = 0; k < m; ++k) idx.push_back(m == 1 ? n - 1 : (k * (n - 1)) / (m - 1));
  std::vector<double> scratch;
  if (!theil_sen(t, y, idx, t.back(), scratch, slope_, now_)) return;
  fitted_ = true;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, idx.size() - 1);
  std::vector<std::size_t> resample(idx.size());
  for (int b = 0; b < draws; ++b) {
    for (auto& r : resample) r = idx[pick(rng)];
    double s = 0, level = 0;
    if (!theil_sen(t, y, resample, t.back(), scratch, s, level)) continue;
    slopes_.push_back(s);
    nows_.push_back(level);
  }
}

Prediction TheilSenBootstrap::time_to(double log_ratio, double coverage) const {
  Prediction p;
  if (answered_without_fit(fitted_ && slopes_.size() >= 20, now_ >= log_ratio, !(slope_ <= 0), "not rising", p)) {
    return p;
  }
  // Crossing time of every bootstrap fit; a fit that does not rise never crosses (+inf).
  std::vector<double> times;
  for (std::size_t b = 0; b < slopes_.size(); ++b) {
    const double gap = log_ratio - nows_[b];
    times.push_back(gap <= 0 ? 0.0 : slopes_[b] > 0 ? gap / slopes_[b] : std::numeric_limits<double>::infinity());
  }
  std::sort(times.begin(), times.end());
  const double tail = 0.5 * (1.0 - coverage);
  const auto at = [&](double q) {
    return times[std::min(times.size() - 1, static_cast<std::size_t>(std::floor(q * static_cast<double>(times.size()))))];
  };
  p.low = at(tail);
  p.high = at(1.0 - tail);
  if (!std::isfinite(p.high)) {
    p.low = p.high = kNaN;
    p.why = "the interval includes never";
    return p;
  }
  p.known = true;
  p.hours = (log_ratio - now_) / slope_;
  return p;
}

DriftRandomWalk::DriftRandomWalk(const std::vector<double>& t, const std::vector<double>& y) {
  const std::size_t n = t.size();
  if (n < 3 || !(t.back() > t.front())) return;
  mu_ = (y.back() - y.front()) / (t.back() - t.front());  // MLE of the drift: total change over total time
  double ss = 0;
  std::size_t used = 0;
  for (std::size_t i = 1; i < n; ++i) {
    const double dt = t[i] - t[i - 1];
    if (!(dt > 0)) continue;
    const double e = y[i] - y[i - 1] - mu_ * dt;
    ss += e * e / dt;
    ++used;
  }
  if (used < 2) return;
  sigma2_ = ss / static_cast<double>(used - 1);
  now_ = y.back();
  fitted_ = sigma2_ > 0;
}

double inverse_gaussian_cdf(double t, double m, double lambda) {
  if (!(t > 0)) return 0.0;
  const double r = std::sqrt(lambda / t);
  const double z1 = r * (t / m - 1.0), z2 = r * (t / m + 1.0);
  return std::min(1.0, normal_cdf(z1) + std::exp(2.0 * lambda / m + log_normal_tail(z2)));
}

Prediction DriftRandomWalk::time_to(double log_ratio, double coverage) const {
  Prediction p;
  const double gap = log_ratio - now_;
  if (answered_without_fit(fitted_, gap <= 0, !(mu_ <= 0), "no rising drift", p)) return p;
  const double m = gap / mu_, lambda = gap * gap / sigma2_;
  // Quantiles by bisection on log t (the CDF is increasing in t).
  auto quantile = [&](double q) {
    double lo = std::log(m) - 40.0, hi = std::log(m) + 40.0;
    for (int i = 0; i < 200 && hi - lo > 1e-10; ++i) {
      const double mid = 0.5 * (lo + hi);
      (inverse_gaussian_cdf(std::exp(mid), m, lambda) >= q ? hi : lo) = mid;
    }
    return std::exp(hi);
  };
  const double tail = 0.5 * (1.0 - coverage);
  p.known = true;
  p.hours = quantile(0.5);
  p.low = quantile(tail);
  p.high = quantile(1.0 - tail);
  return p;
}

}  // namespace causal::prognosis_eval
