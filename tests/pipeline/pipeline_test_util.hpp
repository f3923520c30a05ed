// Test-only helpers for the causal_pipeline tests: simulated SVAR data with known random-walk factors, block
// feeding with per-block times, and a reference that steps causal::estimation::SvarKalmanFilter directly (no pipeline)
// and records what a report at each publish point must contain.
#pragma once

#include "causal/pipeline/factor_stream.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"
#include "causal/estimation/svar_layout.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace causal::test {

using pipeline::RowMajorMatrix;

// The tuned-stream tests' parameters: automatic noise tuned on the first 300 samples (the fixed noise before it),
// a report every 25 samples with fixed-lag twins 16 samples behind.
inline pipeline::FactorStreamParams tuned_stream_params(int channels = 3) {
  pipeline::FactorStreamParams p;
  p.model.channels = channels;
  p.model.lag_order = 1;
  p.noise.automatic = true;
  p.noise.fixed = estimation::NoiseParams{1e-6, 1e-2, 0.5};
  p.noise.calibration_samples = 300;
  p.publish_every = 25;
  p.fixed_lag = 16;
  return p;
}

// N x G samples of y_k = sum_inst x y_j[n] + sum_lag x y_j[n-l] + e_k, e ~ N(0, r), factors a random walk
// with variance q per sample starting U(-0.3, 0.3) (small enough that I - X0 stays well conditioned).
inline RowMajorMatrix simulate_svar(const estimation::SvarLayout& layout, int n, std::uint64_t seed, double q = 1e-5,
                                    double r = 0.05) {
  const int g = layout.channels();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-0.3, 0.3);
  Eigen::VectorXd x(layout.total_factors());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = uniform(rng);
  RowMajorMatrix y = RowMajorMatrix::Zero(n, g);
  for (int t = 0; t < n; ++t) {
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += std::sqrt(q) * normal(rng);
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(g, g);
    Eigen::VectorXd b(g);
    for (int k = 0; k < g; ++k) {
      b[k] = std::sqrt(r) * normal(rng);
      const auto& regs = layout.regressors(k);
      for (int i = 0; i < static_cast<int>(regs.size()); ++i) {
        const double xi = x[layout.offset(k) + i];
        if (regs[static_cast<std::size_t>(i)].lag == 0) {
          a(k, regs[static_cast<std::size_t>(i)].channel) -= xi;
        } else if (t - regs[static_cast<std::size_t>(i)].lag >= 0) {
          b[k] += xi * y(t - regs[static_cast<std::size_t>(i)].lag, regs[static_cast<std::size_t>(i)].channel);
        }
      }
    }
    y.row(t) = a.partialPivLu().solve(b).transpose();
  }
  return y;
}

// Block sizes used to cut a record into frames (irregular on purpose: reports must not depend on framing).
inline std::vector<Eigen::Index> irregular_blocks(Eigen::Index n) {
  static const Eigen::Index pattern[] = {1, 7, 50, 3, 128, 13, 64, 200, 2};
  std::vector<Eigen::Index> sizes;
  Eigen::Index at = 0;
  for (std::size_t i = 0; at < n; ++i) {
    const Eigen::Index s = std::min(pattern[i % (sizeof(pattern) / sizeof(pattern[0]))], n - at);
    sizes.push_back(s);
    at += s;
  }
  return sizes;
}

// What a filter report of outcome k at sample `index` must hold, computed by stepping the filter directly.
struct ExpectedReport {
  std::uint64_t index = 0;
  int outcome = 0;
  Eigen::VectorXd factors, std_devs;
  std::uint64_t innovation_count = 0;
  double innovation_mean = 0.0, nis_mean = 0.0, last_innovation = 0.0, last_innovation_variance = 0.0;
  std::uint64_t rejected = 0;
};

// Steps SvarKalmanFilter over all rows with the given discontinuity flags (one per row, or empty); every
// `publish_every` samples records G expected reports with the innovation statistics accumulated here from
// last_innovation / last_innovation_variance after each Updated step.
inline std::vector<ExpectedReport> reference_reports(const estimation::SvarLayout& layout, const std::vector<estimation::NoiseParams>& noise,
                                                     const RowMajorMatrix& y, const std::vector<bool>& disc,
                                                     std::size_t publish_every) {
  estimation::SvarKalmanFilter filter(layout, noise);
  const int g = layout.channels();
  std::vector<ExpectedReport> out;
  std::vector<std::uint64_t> count(static_cast<std::size_t>(g), 0);
  std::vector<double> sum_e(static_cast<std::size_t>(g), 0.0), sum_nis(static_cast<std::size_t>(g), 0.0);
  for (Eigen::Index n = 0; n < y.rows(); ++n) {
    const bool d = !disc.empty() && disc[static_cast<std::size_t>(n)];
    const estimation::SampleStatus st = filter.step(y.row(n).data(), d);
    if (st == estimation::SampleStatus::Updated) {
      for (int k = 0; k < g; ++k) {
        const double e = filter.last_innovation(k), s = filter.last_innovation_variance(k);
        ++count[static_cast<std::size_t>(k)];
        sum_e[static_cast<std::size_t>(k)] += e;
        sum_nis[static_cast<std::size_t>(k)] += e * e / s;
      }
    }
    if ((static_cast<std::size_t>(n) + 1) % publish_every != 0) continue;
    for (int k = 0; k < g; ++k) {
      ExpectedReport r;
      const auto kk = static_cast<std::size_t>(k);
      r.index = static_cast<std::uint64_t>(n);
      r.outcome = k;
      r.factors = filter.estimate(k);
      r.std_devs = filter.covariance(k).diagonal().cwiseSqrt();
      r.innovation_count = count[kk];
      r.innovation_mean = count[kk] ? sum_e[kk] / static_cast<double>(count[kk]) : std::nan("");
      r.nis_mean = count[kk] ? sum_nis[kk] / static_cast<double>(count[kk]) : std::nan("");
      r.last_innovation = filter.last_innovation(k);
      r.last_innovation_variance = filter.last_innovation_variance(k);
      r.rejected = filter.counters().rejected_non_finite;
      out.push_back(r);
      count[kk] = 0;
      sum_e[kk] = 0.0;
      sum_nis[kk] = 0.0;
    }
  }
  return out;
}

inline std::vector<pipeline::FactorReport> of_kind(const std::vector<pipeline::FactorReport>& all,
                                                   pipeline::EstimateKind kind) {
  std::vector<pipeline::FactorReport> out;
  for (const auto& r : all) {
    if (r.kind == kind) out.push_back(r);
  }
  return out;
}

// Equal, or both NaN (statistics over an empty interval are NaN).
inline bool same_or_both_nan(double a, double b, double tol) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::abs(a - b) <= tol * std::max(1.0, std::abs(b));
}

}  // namespace causal::test
