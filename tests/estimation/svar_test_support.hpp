// Test-only helpers for the estimation tests: a simulator of the SVAR model with known random-walk factors and
// a dense stacked reference filter / RTS smoother written straightforwardly from the textbook equations (full
// F x F covariance, vector measurement, no splitting, no rank-one tricks), as independent truth.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::test {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// G channels, lag order M, every other ModelSpec field at its default.
inline estimation::ModelSpec spec_g(int g, int m) {
  estimation::ModelSpec s;
  s.channels = g;
  s.lag_order = m;
  return s;
}

struct Simulation {
  Eigen::MatrixXd y;  // N x G observations
  Eigen::MatrixXd x;  // N x F true factors, outcome-major (layout order)
};

// x[0] ~ U(-x0_scale, x0_scale) per factor, x[n] = x[n-1] + sqrt(q_k) N(0, 1); y[n] solves the structural
// equations  y_k = sum_inst x y_j[n] + sum_lagged x y_j[n-l] + e_k,  e_k ~ N(0, r_k), i.e.
// (I - X0[n]) y[n] = XL[n] y_lags + e[n]. Lags before the start are taken as 0.
inline Simulation simulate_svar(const estimation::SvarLayout& layout, const std::vector<estimation::NoiseParams>& noise, int n,
                                std::uint64_t seed, double x0_scale = 0.15) {
  const int g = layout.channels();
  const int f = layout.total_factors();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-x0_scale, x0_scale);
  auto nz = [&](int k) { return noise.size() == 1 ? noise[0] : noise[k]; };
  Simulation sim{Eigen::MatrixXd::Zero(n, g), Eigen::MatrixXd::Zero(n, f)};
  Eigen::VectorXd x(f);
  for (int i = 0; i < f; ++i) x[i] = uniform(rng);
  for (int t = 0; t < n; ++t) {
    if (t > 0) {
      for (int k = 0; k < g; ++k) {
        for (int i = 0; i < layout.factor_count(k); ++i) x[layout.offset(k) + i] += std::sqrt(nz(k).q) * normal(rng);
      }
    }
    sim.x.row(t) = x.transpose();
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(g, g);
    Eigen::VectorXd b(g);
    for (int k = 0; k < g; ++k) {
      b[k] = std::sqrt(nz(k).r) * normal(rng);
      const auto& regs = layout.regressors(k);
      for (int i = 0; i < static_cast<int>(regs.size()); ++i) {
        const double xi = x[layout.offset(k) + i];
        if (regs[i].lag == 0) {
          a(k, regs[i].channel) -= xi;
        } else if (t - regs[i].lag >= 0) {
          b[k] += xi * sim.y(t - regs[i].lag, regs[i].channel);
        }
      }
    }
    sim.y.row(t) = a.partialPivLu().solve(b).transpose();
  }
  return sim;
}

// Dense stacked Kalman filter over all F factors with the block-diagonal H[n] (G x F) and the full Joseph form
// P = (I - K H) P (I - K H)^T + K R K^T; RTS with C = P (P + Q)^{-1} by an LU solve. Sample classification is
// re-implemented here (finite check + lag history count) rather than taken from the library.
struct DenseReference {
  std::vector<Eigen::VectorXd> x_filt, x_smooth;
  std::vector<Eigen::MatrixXd> p_filt, p_smooth;
  std::vector<bool> updated;
  std::vector<Eigen::VectorXd> innovations;  // G values where updated

  DenseReference(const estimation::SvarLayout& layout, const std::vector<estimation::NoiseParams>& noise, const Eigen::MatrixXd& y,
                 const std::vector<bool>& disc = {}) {
    const int g = layout.channels(), f = layout.total_factors(), m = layout.lag_order();
    const int n = static_cast<int>(y.rows());
    auto nz = [&](int k) { return noise.size() == 1 ? noise[0] : noise[k]; };
    Eigen::MatrixXd q = Eigen::MatrixXd::Zero(f, f), r = Eigen::MatrixXd::Zero(g, g), p = Eigen::MatrixXd::Zero(f, f);
    for (int k = 0; k < g; ++k) {
      r(k, k) = nz(k).r;
      for (int i = 0; i < layout.factor_count(k); ++i) {
        q(layout.offset(k) + i, layout.offset(k) + i) = nz(k).q;
        p(layout.offset(k) + i, layout.offset(k) + i) = nz(k).p0;
      }
    }
    Eigen::VectorXd x = Eigen::VectorXd::Zero(f);
    int history = 0;
    for (int t = 0; t < n; ++t) {
      if (t > 0) p += q;
      bool finite = y.row(t).allFinite();
      bool use = false;
      if (!finite) {
        history = 0;
      } else {
        if (!disc.empty() && disc[t]) history = 0;
        use = history >= m;
        history = std::min(history + 1, m);
      }
      Eigen::VectorXd e = Eigen::VectorXd::Constant(g, std::nan(""));
      if (use) {
        Eigen::MatrixXd h = Eigen::MatrixXd::Zero(g, f);
        for (int k = 0; k < g; ++k) {
          const auto& regs = layout.regressors(k);
          for (int i = 0; i < static_cast<int>(regs.size()); ++i) {
            h(k, layout.offset(k) + i) = y(t - regs[i].lag, regs[i].channel);
          }
        }
        const Eigen::MatrixXd s = h * p * h.transpose() + r;
        const Eigen::MatrixXd k_gain = s.partialPivLu().solve(h * p).transpose();  // P H^T S^{-1}
        e = y.row(t).transpose() - h * x;
        x += k_gain * e;
        const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(f, f) - k_gain * h;
        p = a * p * a.transpose() + k_gain * r * k_gain.transpose();
      }
      x_filt.push_back(x);
      p_filt.push_back(p);
      updated.push_back(use);
      innovations.push_back(e);
    }
    x_smooth.resize(n);
    p_smooth.resize(n);
    if (n == 0) return;
    x_smooth[n - 1] = x_filt[n - 1];
    p_smooth[n - 1] = p_filt[n - 1];
    for (int t = n - 2; t >= 0; --t) {
      const Eigen::MatrixXd pp = p_filt[t] + q;
      const Eigen::MatrixXd c = pp.partialPivLu().solve(p_filt[t]).transpose();  // P (P + Q)^{-1}, symmetric P
      x_smooth[t] = x_filt[t] + c * (x_smooth[t + 1] - x_filt[t]);
      p_smooth[t] = p_filt[t] + c * (p_smooth[t + 1] - pp) * c.transpose();
    }
  }
};

}  // namespace causal::test
