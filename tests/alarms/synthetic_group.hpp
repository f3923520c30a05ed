// Synthetic condition-level data for the alarm tests, with known causal structure and known changes.
//
// Log condition features of G = 4 channels (one observation per snapshot):
//   y1 = n1,  y2 = n2 + d2(t),  y3 = link * y2 + n3,  y4 = n4,       n_k ~ N(0, sigma^2) i.i.d.
// (deviations from the channel's log level), features f_k = exp(level_k + y_k). Channel 2 (index 1)
// drives channel 3 (index 2) through the causal link; d2(t) is an injected change of channel 2's OWN
// noise (a step or a ramp). The "oracle" innovations of a correctly specified causal model are the
// structural noises n_k + d_k(t) with variance sigma^2: exactly what a converged causal filter would
// report, so the engine can be tested independently of the filter.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/alarms/observation.hpp"

namespace causal::alarms::test {

inline constexpr std::int64_t kT0Ns = 1076581959LL * 1000000000LL;  // 2004-02-12 10:32:39 UTC
inline constexpr std::int64_t kStepNs = 600LL * 1000000000LL;       // 10 min

struct SyntheticConfig {
  int n = 600;
  std::uint64_t seed = 1;
  double sigma = 0.02;   // log-feature noise (2 %)
  double link = 0.8;     // y3 = link * y2 + n3
  // Extra term added to channel `changed` own noise at observation t (in units of sigma).
  int changed = 1;
  std::function<double(int)> own_change = [](int) { return 0.0; };
  // Optional second, independent change on another channel.
  int changed2 = 3;
  std::function<double(int)> own_change2 = [](int) { return 0.0; };
  // Optional single-observation spike on channel `spike_channel` (units of sigma) at `spike_at`.
  int spike_at = -1;
  int spike_channel = 0;
  double spike_sigma = 0.0;
  bool with_factors = false;  // 24 factors (G = 4, M = 1): x32 = link, others 0, plus small noise
};

inline std::vector<std::string> channel_names4() { return {"bearing 1", "bearing 2", "bearing 3", "bearing 4"}; }

// The project's factor order for G = 4, M = 1 (COMMON_RULES): per outcome k, x{k}{j} then xL{k}{j}.
inline std::vector<std::string> factor_names4() {
  std::vector<std::string> names;
  for (int k = 1; k <= 4; ++k) {
    for (const char* prefix : {"x", "xL"})
      for (int j = 1; j <= 4; ++j)
        if (j != k) names.push_back(std::string(prefix) + std::to_string(k) + std::to_string(j));
  }
  return names;
}

inline std::vector<Observation> make_run(const SyntheticConfig& cfg) {
  std::mt19937_64 rng(cfg.seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  const double level[4] = {std::log(0.075), std::log(0.09), std::log(0.1), std::log(0.055)};
  const auto names = factor_names4();
  std::vector<Observation> out;
  out.reserve(static_cast<std::size_t>(cfg.n));
  for (int t = 0; t < cfg.n; ++t) {
    double noise[4];
    for (double& v : noise) v = cfg.sigma * nd(rng);
    noise[cfg.changed] += cfg.sigma * cfg.own_change(t);
    noise[cfg.changed2] += cfg.sigma * cfg.own_change2(t);
    if (t == cfg.spike_at) noise[cfg.spike_channel] += cfg.sigma * cfg.spike_sigma;
    double y[4] = {noise[0], noise[1], 0.0, noise[3]};
    y[2] = cfg.link * y[1] + noise[2];
    Observation o;
    o.index = static_cast<std::uint64_t>(t);
    o.time_ns = kT0Ns + t * kStepNs;
    o.features.resize(4);
    o.innovations.resize(4);
    o.innovation_variances.resize(4);
    for (int k = 0; k < 4; ++k) {
      o.features(k) = std::exp(level[k] + y[k]);
      o.innovations(k) = noise[k];
      o.innovation_variances(k) = cfg.sigma * cfg.sigma;
    }
    if (cfg.with_factors) {
      o.factors.resize(static_cast<Eigen::Index>(names.size()));
      o.factor_std = Eigen::VectorXd::Constant(o.factors.size(), 0.01);
      for (std::size_t i = 0; i < names.size(); ++i)
        o.factors(static_cast<Eigen::Index>(i)) = (names[i] == "x32" ? cfg.link : 0.0) + 0.01 * nd(rng);
    }
    out.push_back(std::move(o));
  }
  return out;
}

// Every event the engine gives for the observations, in order.
inline std::vector<AlarmEvent> run_all(AlarmEngine& e, const std::vector<Observation>& obs) {
  std::vector<AlarmEvent> all;
  for (const auto& o : obs)
    for (auto& ev : e.observe(o)) all.push_back(std::move(ev));
  return all;
}

}  // namespace causal::alarms::test
