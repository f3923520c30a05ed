#include "causal/prognosis/excess_growth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace causal::prognosis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kDriftNodes = 41;      // drift quadrature: mu_hat +- 5 sd
constexpr double kDriftSpan = 5.0;

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// First passage of a Wiener process with drift mu and variance sigma2 per hour over a gap g > 0 by time t.
double passage_known_drift(double g, double mu, double sigma2, double t) {
  const double sd = std::sqrt(sigma2 * t);
  const double first = normal_cdf((mu * t - g) / sd);
  // exp(2 mu g / sigma2) Phi(-(mu t + g) / sd), in logs: the exponent alone overflows for a strong drift.
  const double tail = 0.5 * std::erfc((mu * t + g) / sd / std::sqrt(2.0));
  const double second = tail > 0 ? std::exp(2.0 * mu * g / sigma2 + std::log(tail)) : 0.0;
  return std::min(1.0, first + second);
}

void unknown(TimeToLevel& out, const char* why) {
  out.known = out.reached = false;
  out.hours = out.hours_low = out.hours_high = kNaN;
  out.why = why;
}

struct Blocks {
  std::vector<double> t, z;  // block time (the median of its times), ln of the block's median excess (usable only)
  double last_median = kNaN; // the last block's median excess (usable or not)
};

double median_in_place(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return v.size() % 2 == 1 ? *mid : 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

// Hourly medians of w counted back from t.back() (so the last block is the latest hour); each block at the
// median of its times, where its median value stands for a straight line.
Blocks block_medians(const std::vector<double>& t, const std::vector<double>& w, double floor,
                     double block_hours) {
  Blocks b;
  std::vector<double> cell, times;
  std::vector<std::pair<double, double>> rev;  // (time, median), newest first
  std::size_t i = t.size();
  double end = t.empty() ? 0.0 : t.back();
  while (i > 0) {
    cell.clear();
    times.clear();
    while (i > 0 && t[i - 1] > end - block_hours) {
      if (std::isfinite(w[i - 1])) {
        cell.push_back(w[i - 1]);
        times.push_back(t[i - 1]);
      }
      --i;
    }
    if (!cell.empty()) rev.emplace_back(median_in_place(times), median_in_place(cell));
    end = i > 0 ? std::min(end - block_hours, t[i - 1]) : end;
  }
  if (!rev.empty()) b.last_median = rev.front().second;
  for (auto it = rev.rbegin(); it != rev.rend(); ++it) {
    if (it->second < floor) continue;
    b.t.push_back(it->first);
    b.z.push_back(std::log(it->second));
  }
  return b;
}

}  // namespace

void ExcessGrowthParams::validate() const {
  auto require = [](bool ok, const char* field, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("ExcessGrowthParams.") + field + " " + what);
  };
  require(std::isfinite(block_hours) && block_hours > 0, "block_hours", "must be finite and > 0");
  require(min_blocks >= 3, "min_blocks", "must be >= 3");
  require(std::isfinite(min_excess_sd) && min_excess_sd > 0, "min_excess_sd", "must be finite and > 0");
}

double excess_passage_probability(double gap, double mu, double mu_sd, double sigma2, double t) {
  if (gap <= 0) return 1.0;
  if (!(t > 0) || !(sigma2 > 0)) return 0.0;
  if (!(mu_sd > 0)) return passage_known_drift(gap, mu, sigma2, t);
  // Drift uncertainty integrated out: normal weights on an even grid of mu_hat +- 5 sd (Simpson-free: the
  // weights are renormalised, so the grid's truncation and spacing error stay below 1e-5 of the probability).
  double sum = 0.0, weights = 0.0;
  for (int k = 0; k < kDriftNodes; ++k) {
    const double u = -kDriftSpan + 2.0 * kDriftSpan * k / (kDriftNodes - 1);
    const double wgt = std::exp(-0.5 * u * u);
    sum += wgt * passage_known_drift(gap, mu + u * mu_sd, sigma2, t);
    weights += wgt;
  }
  return sum / weights;
}

namespace {

// One fitted shape: ln w is a Wiener process with drift in the clock s(t) = t (exponential excess) or
// s(t) = ln((tau_now + t) / tau_now), tau from the onset (power-law excess, w = a tau^k); drifts on a grid with
// their posterior weights, the diffusion, and the maximised log-likelihood of the increments.
struct Fit {
  bool log_time = false;
  double tau_now = 1.0;
  std::vector<double> rate, weight;
  double sigma2 = 0.0, mu = 0.0, mu_sd = 0.0;  // the diffusion; the drift's estimate and its sd
  double log_lik = 0.0, model_weight = 1.0;
  double clock(double t) const { return log_time ? std::log1p(t / tau_now) : t; }
  // P(T <= t): inverse-Gaussian first passage of the gap on this shape's clock, mixed over the drifts.
  double cdf(double gap, double t) const {
    if (!(t > 0)) return 0.0;
    const double s = clock(t), sd = std::sqrt(sigma2 * s);
    double sum = 0.0;
    for (std::size_t h = 0; h < rate.size(); ++h) {
      if (weight[h] < 1e-12) continue;
      const double d = rate[h] * s;
      const double first = normal_cdf((d - gap) / sd);
      const double tail = 0.5 * std::erfc((d + gap) / sd / std::sqrt(2.0));
      const double second = tail > 0 ? std::exp(2.0 * rate[h] * gap / sigma2 + std::log(tail)) : 0.0;
      sum += weight[h] * std::min(1.0, first + second);
    }
    return sum;
  }
};

// Whitmore's estimates on the shape's clock v (t or ln tau), the drift's normal posterior on a grid of +- 5 sd.
// An increment between two block summaries of a Wiener process, each over a block of length B hours, has
// variance sigma^2 (dv - B' / 3) with B' the block's length on the clock (the blocks' own averaging): without it
// sigma^2 would come out a third short.
Fit fit_shape(const Blocks& b, double block_hours, bool log_time) {
  Fit f;
  f.log_time = log_time;
  const std::size_t n = b.z.size();
  std::vector<double> v(n), len(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double tau = std::max(b.t[k], 0.5 * block_hours);  // ln tau: a block at the onset counts from its middle
    v[k] = log_time ? std::log(tau) : b.t[k];
    len[k] = log_time ? block_hours / tau : block_hours;
  }
  f.tau_now = std::max(b.t.back(), 0.5 * block_hours);
  const double span = v.back() - v.front();
  f.mu = (b.z.back() - b.z.front()) / span;
  std::vector<double> dv(n, 0.0), r(n, 0.0);
  double ss = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    const double raw = v[k] - v[k - 1];
    dv[k] = std::max(raw - len[k] / 3.0, 0.5 * raw);
    r[k] = b.z[k] - b.z[k - 1] - f.mu * raw;
    ss += r[k] * r[k] / dv[k];
  }
  f.sigma2 = std::max(ss / static_cast<double>(n - 1), 1e-12);
  for (std::size_t k = 1; k < n; ++k)
    f.log_lik -= 0.5 * (std::log(2.0 * 3.141592653589793 * f.sigma2 * dv[k]) + r[k] * r[k] / (f.sigma2 * dv[k]));
  f.mu_sd = std::sqrt(f.sigma2 / span);
  double total = 0.0;
  for (int k = 0; k < kDriftNodes; ++k) {
    const double u = -kDriftSpan + 2.0 * kDriftSpan * k / (kDriftNodes - 1);
    f.rate.push_back(f.mu + u * f.mu_sd);
    f.weight.push_back(std::exp(-0.5 * u * u));
    total += f.weight.back();
  }
  for (double& wgt : f.weight) wgt /= total;
  return f;
}

// Both shapes, weighted by their likelihoods (Bayesian model averaging with equal priors; both have two
// parameters, so this is also the BIC weight).
struct Shapes {
  Fit fits[2];
  double cdf(double gap, double t) const {
    return fits[0].model_weight * fits[0].cdf(gap, t) + fits[1].model_weight * fits[1].cdf(gap, t);
  }
  double quantile(double p, double gap, double horizon) const {
    if (cdf(gap, horizon) < p) return kNaN;
    double lo = 0.0, hi = horizon;
    for (int i = 0; i < 100 && hi - lo > 1e-5 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (cdf(gap, mid) >= p ? hi : lo) = mid;
    }
    return hi;
  }
  const Fit& likelier() const { return fits[0].model_weight >= fits[1].model_weight ? fits[0] : fits[1]; }
};

Shapes fit_shapes(const Blocks& b, double block_hours, bool power_law) {
  Shapes s{{fit_shape(b, block_hours, false), fit_shape(b, block_hours, true)}};
  if (!power_law) {
    s.fits[1].model_weight = 0.0;
    return s;
  }
  const double top = std::max(s.fits[0].log_lik, s.fits[1].log_lik);
  const double w0 = std::exp(s.fits[0].log_lik - top), w1 = std::exp(s.fits[1].log_lik - top);
  s.fits[0].model_weight = w0 / (w0 + w1);
  s.fits[1].model_weight = w1 / (w0 + w1);
  return s;
}

}  // namespace

TimeToLevel excess_growth_time_to(const std::vector<double>& t, const std::vector<double>& w, double noise_std,
                                  double log_ratio, const PrognosisParams& params, bool* too_little_data) {
  const ExcessGrowthParams& growth = params.excess;
  TimeToLevel out;
  if (too_little_data) *too_little_data = false;
  if (t.size() != w.size() || t.empty() || !std::isfinite(noise_std) || !(log_ratio > 0)) {
    if (too_little_data) *too_little_data = true;  // nothing to fit yet: the trend may answer
    unknown(out, "no excess history (no data since the onset, or no healthy scale)");
    return out;
  }
  const double floor = growth.min_excess_sd * std::max(noise_std, params.trend.min_noise_std);
  const Blocks b = block_medians(t, w, floor, growth.block_hours);
  if (b.last_median >= log_ratio) {
    out.known = out.reached = true;
    out.hours = out.hours_low = out.hours_high = 0.0;
    return out;
  }
  char buf[200];
  if (static_cast<int>(b.z.size()) < growth.min_blocks) {
    std::snprintf(buf, sizeof buf, "too few hours with the excess above the noise (%zu of %d hourly medians >= %.3g)",
                  b.z.size(), growth.min_blocks, floor);
    unknown(out, buf);
    if (too_little_data) *too_little_data = true;
    return out;
  }
  const Shapes fit = fit_shapes(b, growth.block_hours, growth.power_law);
  const double gap = std::log(log_ratio) - b.z.back();
  if (gap <= 0) {  // the last usable block is at the level while the latest hour's median is not
    unknown(out, "at the level in an earlier hour, not in the latest one");
    return out;
  }
  // Answer only where the data identify a growth regime: the same one-sided test as the local trend's slope.
  const Fit& best = fit.likelier();
  if (best.mu < params.min_trend_z * best.mu_sd) {
    std::snprintf(buf, sizeof buf, "the log excess has not grown significantly since the onset (%.1f sd)",
                  best.mu / best.mu_sd);
    unknown(out, buf);
    return out;
  }
  const double tail = 0.5 * (1.0 - params.coverage), h = params.max_horizon_hours;
  // The quantiles are times from the last block's time; the answer counts from now (t.back()), never below 0.
  const double since = t.back() - b.t.back();
  const auto from_now = [since](double q) { return std::max(q - since, 0.0); };
  const double median = fit.quantile(0.5, gap, h);
  const double high = fit.quantile(1.0 - tail, gap, h);
  if (!std::isfinite(median) || !std::isfinite(high)) {
    std::snprintf(buf, sizeof buf, "the excess is not growing enough: the %g %% point is beyond the %g h horizon",
                  100.0 * (1.0 - tail), h);
    unknown(out, buf);
    return out;
  }
  out.known = true;
  out.hours = from_now(median);
  out.hours_low = from_now(fit.quantile(tail, gap, h));
  out.hours_high = from_now(high);
  if (out.hours_high > params.max_width_factor * out.hours) {
    std::snprintf(buf, sizeof buf, "interval too wide (%.3g to %.3g h around %.3g h: more than a factor %g)",
                  out.hours_low, out.hours_high, out.hours, params.max_width_factor);
    unknown(out, buf);
  }
  return out;
}

}  // namespace causal::prognosis
