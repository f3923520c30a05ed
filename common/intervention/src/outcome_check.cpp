#include "causal/intervention/outcome_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::intervention {

namespace {

// Normal quantile by bisection on erfc (std only; monotone, 60 halvings are exact to double precision).
double normal_quantile(double p) {
  double lo = -10.0, hi = 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double to_percent(double log_change) { return 100.0 * std::expm1(log_change); }

OutcomeCheck::OutcomeCheck(OutcomeParams params) : params_(params), trust_(params.trust) {
  if (params_.pre_window < 3 || params_.min_pre < 3 || params_.min_pre > params_.pre_window || params_.compare_last < 1 ||
      params_.max_history < static_cast<std::size_t>(params_.pre_window)) {
    throw std::invalid_argument("outcome check: need 3 <= min_pre <= pre_window <= max_history and compare_last >= 1");
  }
}

bool OutcomeCheck::approve(const InterventionPlan& plan) {
  if (seen_.count(plan.request_id) > 0) return false;
  seen_[plan.request_id] = true;
  Pending p;
  p.plan = plan;
  pending_[plan.request_id] = p;
  return true;
}

std::vector<InterventionPlan> OutcomeCheck::due(const std::string& group, std::uint64_t index) const {
  std::vector<InterventionPlan> out;
  for (const auto& [id, p] : pending_) {
    if (!p.frozen && p.plan.asset_group == group && p.plan.start <= index + 1) out.push_back(p.plan);
  }
  return out;
}

std::optional<OutcomeCheck::Forecast> OutcomeCheck::fit_forecast(const std::string& group, int target,
                                                                 std::uint64_t start) const {
  const auto h = history_.find(group);
  if (h == history_.end() || start == 0) return std::nullopt;
  // The last W consecutive snapshots before the start (a gap ends the window: the forecast needs s - 1).
  std::vector<double> z;
  for (std::uint64_t t = start; t-- > 0 && z.size() < static_cast<std::size_t>(params_.pre_window);) {
    const auto it = h->second.find(t);
    if (it == h->second.end() || static_cast<Eigen::Index>(target) >= it->second.size()) break;
    z.push_back(it->second[target]);
  }
  if (z.size() < static_cast<std::size_t>(params_.min_pre)) return std::nullopt;
  std::reverse(z.begin(), z.end());
  const double n = static_cast<double>(z.size());
  double mean = 0.0;
  for (double v : z) mean += v / n;
  double var = 0.0, cov = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    var += (z[i] - mean) * (z[i] - mean);
    if (i > 0) cov += (z[i] - mean) * (z[i - 1] - mean);
  }
  Forecast f;
  f.mean = mean;
  f.rho = var > 0.0 ? std::clamp(cov / var, 0.0, 0.99) : 0.0;
  f.variance = var / (n - 1.0);
  f.last_dev = z.back() - mean;
  f.window = static_cast<int>(z.size());
  return f;
}

double OutcomeCheck::forecast_sd(const Pending& p) const {
  const Forecast& f = p.forecast;
  const double r = f.rho, s2 = (1.0 - r * r) * f.variance;
  const double k = static_cast<double>(p.compare_to - p.compare_from + 1);
  double sum = 0.0;
  for (std::uint64_t t = p.compare_from; t <= p.compare_to; ++t) {
    for (std::uint64_t u = p.compare_from; u <= p.compare_to; ++u) {
      const double ht = static_cast<double>(t - p.plan.start + 1), hu = static_cast<double>(u - p.plan.start + 1);
      const double lag = std::abs(static_cast<double>(t) - static_cast<double>(u));
      // Cov of two AR(1) forecast errors h_t and h_u steps ahead (O3); rho = 0: s2 when t = u.
      sum += r > 0.0 ? std::pow(r, lag) * (1.0 - std::pow(r, 2.0 * std::min(ht, hu))) / (1.0 - r * r)
                     : (t == u ? 1.0 : 0.0);
    }
  }
  const double w_eff = std::max(1.0, f.window * (1.0 - r) / (1.0 + r));
  return std::sqrt(s2 * sum / (k * k) + f.variance / w_eff);
}

void OutcomeCheck::freeze(const std::string& request_id, const Prediction& prediction, std::vector<Outcome>& done) {
  const auto it = pending_.find(request_id);
  if (it == pending_.end() || it->second.frozen) return;
  Pending& p = it->second;
  p.frozen = true;
  p.prediction = prediction;
  if (!prediction.ok) {
    done.push_back(finish(p, "no_forecast", "the twin predicted no effect: " + prediction.why));
    pending_.erase(it);
    return;
  }
  const std::uint64_t end = p.plan.start + p.plan.duration - 1;
  if (prediction.steady_state) {
    p.compare_to = end;
    p.compare_from = end + 1 - std::min<std::uint64_t>(p.plan.duration, static_cast<std::uint64_t>(params_.compare_last));
  } else {
    p.compare_from = p.compare_to = p.plan.start + static_cast<std::uint64_t>(prediction.horizon);
    if (p.compare_to > end) {
      done.push_back(finish(p, "no_forecast", "the window (" + std::to_string(p.plan.duration) +
                                                  " snapshots) ends before the twin's horizon (" +
                                                  std::to_string(prediction.horizon) + " snapshots after the start)"));
      pending_.erase(it);
      return;
    }
  }
  const auto f = fit_forecast(p.plan.asset_group, p.plan.target, p.plan.start);
  if (!f) {
    done.push_back(finish(p, "no_forecast", "fewer than " + std::to_string(params_.min_pre) +
                                                " consecutive snapshots before the start to forecast from"));
    pending_.erase(it);
    return;
  }
  p.forecast = *f;
}

Outcome OutcomeCheck::finish(const Pending& p, const std::string& status, const std::string& why) {
  Outcome o;
  o.plan = p.plan;
  o.status = status;
  o.why = why;
  o.compare_from = p.compare_from;
  o.compare_to = p.compare_to;
  o.predicted = p.prediction.effect;
  o.predicted_low = p.prediction.low;
  o.predicted_high = p.prediction.high;
  o.coverage = p.prediction.coverage;
  o.observed = std::numeric_limits<double>::quiet_NaN();
  if (status == "checked") {
    const auto& h = history_[p.plan.asset_group];
    double sum = 0.0;
    for (std::uint64_t t = p.compare_from; t <= p.compare_to; ++t) {
      const double step = static_cast<double>(t - p.plan.start + 1);
      const double forecast = p.forecast.mean + std::pow(p.forecast.rho, step) * p.forecast.last_dev;  // (O1)
      sum += h.at(t)[p.plan.target] - forecast;
    }
    o.observed = sum / static_cast<double>(p.compare_to - p.compare_from + 1);  // (O2)
    o.forecast_sd = forecast_sd(p);
    const double q = normal_quantile(0.5 * (1.0 + p.prediction.coverage));
    o.check_low = p.prediction.low - q * o.forecast_sd;
    o.check_high = p.prediction.high + q * o.forecast_sd;
    o.inside = o.check_low <= o.observed && o.observed <= o.check_high;
    o.improved = o.observed < 0.0;
    trust_.record(p.plan.asset_group, p.plan.lever, p.plan.target, o.inside, o.improved);
  }
  o.lever_trust = trust_.trust(p.plan.asset_group, p.plan.lever, p.plan.target);
  o.lever_claimed = trust_.claimed(p.plan.asset_group, p.plan.lever, p.plan.target);
  return o;
}

void OutcomeCheck::check_ready(const std::string& group, std::uint64_t index, std::vector<Outcome>& done) {
  const auto& h = history_[group];
  for (auto it = pending_.begin(); it != pending_.end();) {
    const Pending& p = it->second;
    if (!p.frozen || p.plan.asset_group != group || index < p.compare_to) {
      ++it;
      continue;
    }
    bool complete = true;
    for (std::uint64_t t = p.compare_from; t <= p.compare_to; ++t) complete = complete && h.count(t) > 0;
    done.push_back(complete ? finish(p, "checked", "")
                            : finish(p, "no_data", "snapshots of the comparison window were not observed"));
    it = pending_.erase(it);
  }
}

void OutcomeCheck::observe(const std::string& group, std::uint64_t index, const Eigen::VectorXd& log_levels,
                           std::vector<Outcome>& done) {
  if (!log_levels.allFinite()) {
    ++rejected_;  // a gap for the check: an outcome needing this snapshot ends as no_data
  } else {
    auto& h = history_[group];
    h[index] = log_levels;
    while (h.size() > params_.max_history) h.erase(h.begin());
  }
  check_ready(group, index, done);
}

}  // namespace causal::intervention
