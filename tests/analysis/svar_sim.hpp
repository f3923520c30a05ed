// Test helper: structural VARs with known coefficients and an independent simulator.
//
// The simulator evaluates (S1) y_k[n] = sum_j A0(k,j) y_j[n] + sum_l A_l(k,:) y[n-l] + e_k[n] channel by
// channel in the causal order (plain substitution), so it shares no code with the library's LU solves.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace causal::analysis::test {

struct TrueSvar {
  Eigen::MatrixXd a0;                 // strictly lower triangular after permuting by `order`
  std::vector<Eigen::MatrixXd> lags;  // A_1..A_M
  std::vector<int> order;             // causes first
};

enum class NoiseKind { uniform, laplace, gaussian };

// Unit-variance noise scaled per channel by sd.
inline Eigen::MatrixXd draw_noise(std::mt19937_64& rng, int n, const Eigen::VectorXd& sd, NoiseKind kind) {
  const int g = static_cast<int>(sd.size());
  Eigen::MatrixXd e(n, g);
  std::uniform_real_distribution<double> uni(-std::sqrt(3.0), std::sqrt(3.0));  // variance 1
  std::exponential_distribution<double> expo(std::sqrt(2.0));                    // Laplace(0, 1/sqrt 2): variance 1
  std::bernoulli_distribution coin(0.5);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < g; ++c) {
      double v = 0.0;
      switch (kind) {
        case NoiseKind::uniform: v = uni(rng); break;
        case NoiseKind::laplace: v = coin(rng) ? expo(rng) : -expo(rng); break;
        case NoiseKind::gaussian: v = normal(rng); break;
      }
      e(r, c) = sd(c) * v;
    }
  }
  return e;
}

// Reduced-form companion spectral radius, computed densely (independent of the library).
inline double true_spectral_radius(const TrueSvar& s) {
  const int g = static_cast<int>(s.a0.rows());
  const int m = static_cast<int>(s.lags.size());
  const Eigen::MatrixXd inv = (Eigen::MatrixXd::Identity(g, g) - s.a0).inverse();  // tests may invert a 4x4
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(g * m, g * m);
  for (int l = 0; l < m; ++l) c.block(0, l * g, g, g) = inv * s.lags[l];
  if (m > 1) c.block(g, 0, g * (m - 1), g * (m - 1)).setIdentity();
  return Eigen::EigenSolver<Eigen::MatrixXd>(c, false).eigenvalues().cwiseAbs().maxCoeff();
}

// Random acyclic SVAR: a random causal order; every pair order[a] -> order[b] (a < b) has an instantaneous
// link with |coefficient| in [edge_min, edge_max] and a random sign; self lags `self_lag`; each cross lag
// uniform in [-cross_lag, cross_lag]. Redrawn until the companion spectral radius is < max_radius.
inline TrueSvar random_svar(std::mt19937_64& rng, int g, int m, double edge_min = 0.4, double edge_max = 0.8,
                            double self_lag = 0.4, double cross_lag = 0.15, double max_radius = 0.9) {
  std::uniform_real_distribution<double> mag(edge_min, edge_max);
  std::uniform_real_distribution<double> cross(-cross_lag, cross_lag);
  std::bernoulli_distribution coin(0.5);
  for (;;) {
    TrueSvar s;
    s.order.resize(static_cast<std::size_t>(g));
    std::iota(s.order.begin(), s.order.end(), 0);
    std::shuffle(s.order.begin(), s.order.end(), rng);
    s.a0 = Eigen::MatrixXd::Zero(g, g);
    for (int a = 0; a < g; ++a)
      for (int b = a + 1; b < g; ++b) s.a0(s.order[b], s.order[a]) = (coin(rng) ? 1.0 : -1.0) * mag(rng);
    for (int l = 0; l < m; ++l) {
      Eigen::MatrixXd a(g, g);
      for (int k = 0; k < g; ++k)
        for (int j = 0; j < g; ++j) a(k, j) = k == j ? (l == 0 ? self_lag : 0.0) : cross(rng);
      s.lags.push_back(a);
    }
    if (true_spectral_radius(s) < max_radius) return s;
  }
}

// Simulates (S1) from zero history. forced (optional, N x G): a finite entry overrides that channel's value
// at that sample (the channel's equation is replaced; others see the forced value).
inline Eigen::MatrixXd simulate(const TrueSvar& s, const Eigen::MatrixXd& e, const Eigen::MatrixXd* forced = nullptr) {
  const int n = static_cast<int>(e.rows());
  const int g = static_cast<int>(e.cols());
  const int m = static_cast<int>(s.lags.size());
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(n, g);
  for (int t = 0; t < n; ++t) {
    for (int k : s.order) {
      if (forced != nullptr && std::isfinite((*forced)(t, k))) {
        y(t, k) = (*forced)(t, k);
        continue;
      }
      double v = e(t, k);
      for (int j = 0; j < g; ++j) v += s.a0(k, j) * y(t, j);  // parents come earlier in `order`
      for (int l = 1; l <= m && t - l >= 0; ++l)
        for (int j = 0; j < g; ++j) v += s.lags[l - 1](k, j) * y(t - l, j);
      y(t, k) = v;
    }
  }
  return y;
}

inline Eigen::MatrixXd no_force(int n, int g) {
  return Eigen::MatrixXd::Constant(n, g, std::numeric_limits<double>::quiet_NaN());
}

}  // namespace causal::analysis::test
