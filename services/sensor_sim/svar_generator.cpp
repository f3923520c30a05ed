#include "svar_generator.hpp"

#include "seed_mix.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace causal::sim {

namespace {

enum Stream : std::uint64_t { kModelStream = 1, kNoiseStream = 2 };

std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t group, Stream stream) {
  return mix(mix(mix(seed) ^ group) ^ static_cast<std::uint64_t>(stream));
}

// [0, 1) from the top 53 bits: defined by the bits alone (std::uniform_real_distribution is not portable).
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
double between(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * unit(rng); }
double sign(std::mt19937_64& rng) { return (rng() >> 63) != 0 ? 1.0 : -1.0; }

}  // namespace

SvarModel make_group_model(std::uint64_t seed, std::uint64_t group, int channels, int lag_order) {
  if (channels < 1 || channels > 64) throw std::invalid_argument("channels must be in 1..64");
  if (lag_order < 1 || lag_order > 8) throw std::invalid_argument("lag order must be in 1..8");
  std::mt19937_64 rng(stream_seed(seed, group, kModelStream));
  const int g = channels;
  for (;;) {
    SvarModel m;
    m.instantaneous = Eigen::MatrixXd::Zero(g, g);
    for (int k = 0; k < g; ++k)
      for (int j = 0; j < k; ++j) m.instantaneous(k, j) = sign(rng) * between(rng, 0.2, 0.5);
    for (int l = 0; l < lag_order; ++l) {
      Eigen::MatrixXd a = Eigen::MatrixXd::Zero(g, g);
      for (int k = 0; k < g; ++k)
        for (int j = 0; j < g; ++j)
          if (j != k) a(k, j) = between(rng, -0.3, 0.3);
      m.lags.push_back(a);
    }
    m.noise_sd.resize(g);
    for (int k = 0; k < g; ++k) m.noise_sd[k] = between(rng, 0.5, 1.5);
    if (companion_spectral_radius(m) < 0.9) return m;
  }
}

double companion_spectral_radius(const SvarModel& model) {
  const int g = model.channels();
  const int m = model.lag_order();
  // Reduced form y[n] = (I - A0)^-1 (sum_l A_l y[n-l] + e[n]).
  const Eigen::MatrixXd i_minus_a0 = Eigen::MatrixXd::Identity(g, g) - model.instantaneous;
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(i_minus_a0);
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(g * m, g * m);
  for (int l = 0; l < m; ++l) companion.block(0, l * g, g, g) = lu.solve(model.lags[static_cast<std::size_t>(l)]);
  if (m > 1) companion.block(g, 0, g * (m - 1), g * (m - 1)).setIdentity();
  return Eigen::EigenSolver<Eigen::MatrixXd>(companion, false).eigenvalues().cwiseAbs().maxCoeff();
}

std::string describe_factors(const SvarModel& model) {
  const int g = model.channels();
  std::string text;
  char buf[64];
  auto add = [&](const std::string& name, double v) {
    std::snprintf(buf, sizeof buf, "%s%s=%+.3f", text.empty() ? "" : " ", name.c_str(), v);
    text += buf;
  };
  for (int k = 0; k < g; ++k)
    for (int j = 0; j < g; ++j)
      if (j != k) add("x" + std::to_string(k + 1) + std::to_string(j + 1), model.instantaneous(k, j));
  for (int l = 1; l <= model.lag_order(); ++l) {
    const std::string prefix = l == 1 ? "xL" : "xL" + std::to_string(l);
    for (int k = 0; k < g; ++k)
      for (int j = 0; j < g; ++j)
        if (j != k) add(prefix + std::to_string(k + 1) + std::to_string(j + 1), model.lags[static_cast<std::size_t>(l - 1)](k, j));
  }
  return text;
}

SvarGenerator::SvarGenerator(SvarModel model, std::uint64_t seed, std::uint64_t group)
    : model_(std::move(model)),
      rng_(stream_seed(seed, group, kNoiseStream)),
      history_(Eigen::MatrixXd::Zero(model_.lag_order(), model_.channels())),
      current_(model_.channels()) {}

double SvarGenerator::uniform_noise() { return std::sqrt(3.0) * (2.0 * unit(rng_) - 1.0); }

void SvarGenerator::next(Eigen::Index rows, Eigen::MatrixXd& out) {
  const int g = model_.channels();
  const int m = model_.lag_order();
  out.resize(rows, g);
  for (Eigen::Index r = 0; r < rows; ++r) {
    // Channels in index order: every instantaneous parent j < k is already computed.
    for (int k = 0; k < g; ++k) {
      double v = model_.noise_sd[k] * uniform_noise();
      for (int j = 0; j < k; ++j) v += model_.instantaneous(k, j) * current_[j];
      for (int l = 1; l <= m; ++l) {
        const auto past = history_.row(static_cast<Eigen::Index>((generated_ + static_cast<std::uint64_t>(m - l)) %
                                                                 static_cast<std::uint64_t>(m)));
        v += model_.lags[static_cast<std::size_t>(l - 1)].row(k).dot(past);
      }
      current_[k] = v;
    }
    // The oldest row (y[n-M]) is no longer needed: y[n] takes its slot.
    history_.row(static_cast<Eigen::Index>(generated_ % static_cast<std::uint64_t>(m))) = current_.transpose();
    out.row(r) = current_.transpose();
    ++generated_;
  }
}

}  // namespace causal::sim
