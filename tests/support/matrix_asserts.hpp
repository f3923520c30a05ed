// ASSERT-style helpers for Eigen matrices: report the worst element, its position and both values.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

namespace causal::test {

// Max |a - b| over all elements; fails on shape mismatch or any non-finite element.
template <typename A, typename B>
::testing::AssertionResult MatricesNear(const char* a_expr, const char* b_expr, const char* /*tol_expr*/,
                                        const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b,
                                        double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << a_expr << " is " << a.rows() << "x" << a.cols() << " but " << b_expr
                                         << " is " << b.rows() << "x" << b.cols();
  }
  double worst = -1.0;
  Eigen::Index wr = 0, wc = 0;
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    for (Eigen::Index c = 0; c < a.cols(); ++c) {
      const double x = static_cast<double>(a(r, c));
      const double y = static_cast<double>(b(r, c));
      if (!std::isfinite(x) || !std::isfinite(y)) {
        return ::testing::AssertionFailure() << "non-finite element at (" << r << "," << c << "): " << a_expr
                                             << "=" << x << ", " << b_expr << "=" << y;
      }
      const double d = std::abs(x - y);
      if (d > worst) {
        worst = d;
        wr = r;
        wc = c;
      }
    }
  }
  if (worst <= tol) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os.precision(17);
  os << "max |" << a_expr << " - " << b_expr << "| = " << worst << " > " << tol << " at (" << wr << "," << wc
     << "): " << a(wr, wc) << " vs " << b(wr, wc);
  return ::testing::AssertionFailure() << os.str();
}

// Symmetric to within tol and all eigenvalues > min_eig.
template <typename A>
::testing::AssertionResult IsSymmetricPositiveDefinite(const char* a_expr, const char* /*min_eig_expr*/,
                                                       const Eigen::MatrixBase<A>& a, double min_eig) {
  if (a.rows() != a.cols()) return ::testing::AssertionFailure() << a_expr << " is not square";
  const Eigen::MatrixXd m = a.template cast<double>();
  const double asym = (m - m.transpose()).cwiseAbs().maxCoeff();
  if (asym > 1e-12 * std::max(1.0, m.cwiseAbs().maxCoeff())) {
    return ::testing::AssertionFailure() << a_expr << " is not symmetric: max |P - P^T| = " << asym;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m, Eigen::EigenvaluesOnly);
  if (es.eigenvalues().minCoeff() <= min_eig) {
    return ::testing::AssertionFailure() << a_expr << " has eigenvalue " << es.eigenvalues().minCoeff()
                                         << " <= " << min_eig;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace causal::test

#define ASSERT_MATRIX_NEAR(a, b, tol) ASSERT_PRED_FORMAT3(::causal::test::MatricesNear, a, b, tol)
#define EXPECT_MATRIX_NEAR(a, b, tol) EXPECT_PRED_FORMAT3(::causal::test::MatricesNear, a, b, tol)
#define ASSERT_SPD(a, min_eig) ASSERT_PRED_FORMAT2(::causal::test::IsSymmetricPositiveDefinite, a, min_eig)
#define EXPECT_SPD(a, min_eig) EXPECT_PRED_FORMAT2(::causal::test::IsSymmetricPositiveDefinite, a, min_eig)
