// How far a learned VAR-LiNGAM order can be trusted (analysis/order_trust.hpp): identifiable (uniform
// noise) orders are trusted, Gaussian noise (LiNGAM cannot order it) is not, on several seeds each.
#include "causal/analysis/order_trust.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

using namespace causal::analysis;

// x2 -> x1 at once (0.8) plus AR(1) terms; x3 independent. n samples.
Eigen::MatrixXd linked_pair(int n, bool gaussian, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.035, 0.035);
  std::normal_distribution<double> g(0.0, 0.02);
  auto noise = [&] { return gaussian ? g(rng) : u(rng); };
  Eigen::MatrixXd x(n, 3);
  Eigen::RowVector3d prev = Eigen::RowVector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const double x2 = 0.5 * prev[1] + noise();
    const double x1 = 0.8 * x2 + 0.3 * prev[0] + noise();
    const double x3 = 0.4 * prev[2] + noise();
    x.row(i) << x1, x2, x3;
    prev = x.row(i);
  }
  return x;
}

TEST(OrderTrust, JarqueBeraSeparatesUniformFromGaussian) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> g;
  int uniform_rejected = 0, gaussian_rejected = 0;
  const int trials = 100;
  for (int t = 0; t < trials; ++t) {
    Eigen::VectorXd a(400), b(400);
    for (int i = 0; i < 400; ++i) {
      a[i] = u(rng);
      b[i] = g(rng);
    }
    uniform_rejected += jarque_bera_p(a) < 0.05;
    gaussian_rejected += jarque_bera_p(b) < 0.05;
  }
  EXPECT_EQ(uniform_rejected, trials);
  EXPECT_LE(gaussian_rejected, 12) << "a 5 % test (JB is conservative at n = 400)";
}

TEST(OrderTrust, UniformNoiseIsTrustedGaussianIsNot) {
  int trusted_uniform = 0, trusted_gaussian = 0;
  const int seeds = 10;
  for (int s = 0; s < seeds; ++s) {
    const auto uni = assess_order(var_lingam(linked_pair(300, false, 100 + s)));
    const auto gau = assess_order(var_lingam(linked_pair(300, true, 100 + s)));
    EXPECT_GE(uni.material_pairs, 1) << uni.summary;
    EXPECT_GE(gau.confidence, 0.0);
    EXPECT_LE(gau.confidence, 1.0);
    trusted_uniform += uni.trusted ? 1 : 0;
    trusted_gaussian += gau.trusted ? 1 : 0;
    std::printf("seed %d uniform: %s\n         gaussian: %s\n", s, uni.summary.c_str(), gau.summary.c_str());
  }
  EXPECT_GE(trusted_uniform, 8) << "identifiable orders must mostly be trusted";
  EXPECT_LE(trusted_gaussian, 1) << "LiNGAM cannot order Gaussian noise";
}

TEST(OrderTrust, DeterministicForASeed) {
  const auto r = var_lingam(linked_pair(300, false, 1));
  EXPECT_EQ(assess_order(r).summary, assess_order(r).summary);
}

}  // namespace
