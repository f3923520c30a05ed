// Simulated asset groups for sensor-sim: each group is a stable structural VAR with known causal factors,
//
//     y_k[n] = sum_{j<k} x_kj y_j[n] + sum_{l=1..M} sum_{j!=k} xL{l}_kj y_j[n-l] + e_k[n],
//
// i.e. the README's model with constant factors, an acyclic instantaneous part (channel j < k may drive k at
// once: simulation is plain substitution, no solve) and no self-lags (the shipped sample-level model has none).
// Noise is uniform (non-Gaussian, so VAR-LiNGAM can order the channels) with a per-channel standard deviation.
// Everything is a function of (seed, group index): the same seed gives the same factors and the same samples,
// whatever the frame size. Eigen and the standard library only.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace causal::sim {

struct SvarModel {
  Eigen::MatrixXd instantaneous;      // G x G, (k, j) = x{k}{j}; strictly lower triangular
  std::vector<Eigen::MatrixXd> lags;  // M matrices G x G, lags[l-1](k, j) = xL{l}{k}{j}; zero diagonal
  Eigen::VectorXd noise_sd;           // standard deviation of e_k
  int channels() const { return static_cast<int>(instantaneous.rows()); }
  int lag_order() const { return static_cast<int>(lags.size()); }
};

// The known factors of asset group `group`: instantaneous links of magnitude 0.2..0.5 and random sign, cross
// lags within +-0.3, noise sd 0.5..1.5, redrawn (deterministically) until the reduced form is stable with a
// companion spectral radius below 0.9. Throws std::invalid_argument unless 1 <= channels <= 64, 1 <= lag_order <= 8.
SvarModel make_group_model(std::uint64_t seed, std::uint64_t group, int channels, int lag_order);

// Spectral radius of the reduced form's companion matrix (< 1: stable).
double companion_spectral_radius(const SvarModel& model);

// "x21=+0.314 x31=-0.250 ... xL12=+0.120 ...": every factor by its README name (1-based; xL2.. for lag 2..).
std::string describe_factors(const SvarModel& model);

// Streams samples of one group. Starts from zero history; the stream does not depend on how it is cut into
// frames (next(10) twice == next(20)).
class SvarGenerator {
 public:
  SvarGenerator(SvarModel model, std::uint64_t seed, std::uint64_t group);

  // Fills `out` (resized to rows x G) with the next `rows` samples.
  void next(Eigen::Index rows, Eigen::MatrixXd& out);

  const SvarModel& model() const { return model_; }
  std::uint64_t samples_generated() const { return generated_; }

 private:
  double uniform_noise();  // uniform on [-sqrt 3, sqrt 3): mean 0, variance 1

  SvarModel model_;
  std::mt19937_64 rng_;       // output sequence fixed by the standard: same seed, same samples everywhere
  Eigen::MatrixXd history_;   // M x G ring of past samples; row (generated_ - l) mod M is y[n - l]
  Eigen::VectorXd current_;
  std::uint64_t generated_ = 0;
};

}  // namespace causal::sim
