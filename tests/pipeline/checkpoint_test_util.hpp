// Test-only helpers for the checkpoint tests: save -> bytes -> restore round trips, and BITWISE comparisons
// of everything a stream outputs (a restarted stream must continue exactly, not approximately: NaN == NaN
// and -0.0 != +0.0 here).
#pragma once

#include "causal/pipeline/asset_pipeline.hpp"
#include "causal/estimation/state_archive.hpp"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace causal::test {

template <class T>
std::string checkpoint_of(const T& object) {
  estimation::StateWriter w;
  object.save(w);
  return w.bytes();
}

// Restores `object` from `bytes` and checks that the whole checkpoint was read.
template <class T>
void restore_from(T& object, const std::string& bytes) {
  estimation::StateReader r(bytes);
  object.restore(r);
  EXPECT_TRUE(r.at_end()) << "restore() left bytes unread";
}

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <class M>
bool same_bits(const M& a, const M& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0);
}

inline void expect_identical(const pipeline::FactorReport& a, const pipeline::FactorReport& b, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.sample_index, b.sample_index);
  EXPECT_EQ(a.time_ns, b.time_ns);
  EXPECT_TRUE(same_bits(a.factors, b.factors));
  EXPECT_TRUE(same_bits(a.std_devs, b.std_devs));
  EXPECT_TRUE(same_bits(a.covariance, b.covariance));
  EXPECT_EQ(a.innovation_count, b.innovation_count);
  EXPECT_TRUE(same_bits(a.innovation_mean, b.innovation_mean));
  EXPECT_TRUE(same_bits(a.nis_mean, b.nis_mean));
  EXPECT_TRUE(same_bits(a.last_innovation, b.last_innovation));
  EXPECT_TRUE(same_bits(a.last_innovation_variance, b.last_innovation_variance));
  EXPECT_EQ(a.rejected, b.rejected);
  EXPECT_TRUE(same_bits(a.q, b.q));
  EXPECT_TRUE(same_bits(a.r, b.r));
}

inline void expect_identical(const std::vector<pipeline::FactorReport>& got,
                             const std::vector<pipeline::FactorReport>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i) expect_identical(got[i], want[i], what + " report " + std::to_string(i));
}

inline void expect_identical(const std::vector<pipeline::ConditionSample>& got,
                             const std::vector<pipeline::ConditionSample>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    SCOPED_TRACE("condition vector " + std::to_string(i));
    EXPECT_EQ(got[i].snapshot_index, want[i].snapshot_index);
    EXPECT_EQ(got[i].time_ns, want[i].time_ns);
    EXPECT_TRUE(same_bits(got[i].values, want[i].values));
    EXPECT_TRUE(same_bits(got[i].model_input, want[i].model_input));
    EXPECT_EQ(got[i].samples, want[i].samples);
    EXPECT_EQ(got[i].discontinuity, want[i].discontinuity);
  }
}

template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

// n x G series of a structural VAR(1) with uniform (non-Gaussian) unit-variance shocks, so VAR-LiNGAM can
// order it: instantaneous links 2 -> 0 (0.7), 0 -> 1 (0.6), 2 -> 3 (0.5) for G = 4, scaled by `scale` and
// shifted to `level` (condition-level log levels are far from zero: the centre matters).
inline Eigen::MatrixXd simulate_lingam(int n, std::uint64_t seed, double scale, double level) {
  const int g = 4;
  Eigen::MatrixXd b0 = Eigen::MatrixXd::Zero(g, g);
  b0(0, 2) = 0.7;
  b0(1, 0) = 0.6;
  b0(3, 2) = 0.5;
  const Eigen::MatrixXd a1 = 0.3 * Eigen::MatrixXd::Identity(g, g);
  const Eigen::MatrixXd inv = (Eigen::MatrixXd::Identity(g, g) - b0).inverse();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-std::sqrt(3.0), std::sqrt(3.0));
  Eigen::MatrixXd z(n, g);
  Eigen::VectorXd prev = Eigen::VectorXd::Zero(g);
  for (int t = -50; t < n; ++t) {
    Eigen::VectorXd e(g);
    for (int k = 0; k < g; ++k) e[k] = u(rng);
    prev = inv * (a1 * prev + e);
    if (t >= 0) z.row(t) = (scale * prev).transpose().array() + level;
  }
  return z;
}

}  // namespace causal::test
