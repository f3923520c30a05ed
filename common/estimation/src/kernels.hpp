// Per-outcome Kalman kernels on raw column-major arrays, templated on the outcome's state dimension D so that
// common sizes (1..kMaxFixedDim) get compile-time trip counts (unrolled, vectorised, scratch on the stack).
// D = 0 means "dimension known at run time" and uses caller-owned scratch, so no kernel allocates per step.
// Plain loops rather than fixed-size Eigen expressions: same speed here, a fraction of the compile time/memory.
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>

namespace causal::detail {

constexpr int kMaxFixedDim = 12;

// Entry points that run the kernels (not the kernels themselves: they are inlined into these) are compiled
// twice on x86-64 GCC, for the baseline and for x86-64-v3 (AVX2 + FMA), and the loader picks the clone the
// CPU supports (GCC function multi-versioning): portable binaries that still use wide vectors.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(CAUSAL_CORE_NO_CLONES)
#define CAUSAL_CORE_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CAUSAL_CORE_CLONES
#endif
// Kernels are force-inlined into those entry points so that each clone gets its own vector code.
#if defined(__GNUC__)
#define CAUSAL_CORE_KERNEL __attribute__((always_inline)) inline
#else
#define CAUSAL_CORE_KERNEL inline
#endif

// Scratch doubles a D = 0 kernel needs for dimension d (covers every kernel below).
inline std::size_t kernel_work_size(int d) {
  return static_cast<std::size_t>(4 * d + 4 * d * d);  // rts_step: 4 d^2 + 2 d
}

// Stack scratch for fixed D, caller scratch for D = 0.
template <int D>
struct Scratch {
  double buf[4 * D + 4 * D * D];
  explicit Scratch(double* /*unused*/) {}
  double* get() { return buf; }
};
template <>
struct Scratch<0> {
  double* ptr;
  explicit Scratch(double* work) : ptr(work) {}
  double* get() { return ptr; }
};

struct UpdateResult {
  double e;  // innovation y - h^T x[n|n-1]
  double s;  // innovation variance h^T P[n|n-1] h + r
};

// Time update of the random walk x[n+1] = x[n] + w, w ~ N(0, q I): x unchanged, P += q I.
template <int D>
CAUSAL_CORE_KERNEL void predict(int d_rt, double* p, double q) {
  const int d = D > 0 ? D : d_rt;
  for (int i = 0; i < d; ++i) p[i * d + i] += q;
}

// Scalar measurement update y = h^T x + eps, eps ~ N(0, r), covariance in Joseph form
//   P+ = (I - K h^T) P (I - K h^T)^T + r K K^T            (Bucy & Joseph 1968; Simon, "Optimal State
//                                                          Estimation", 2006, eq. 5.19)
// For a scalar measurement it expands exactly, for ANY gain K, into the symmetric rank-2 update
//   P+ = P - K u^T - u K^T + S K K^T = P - K z^T - z K^T,   u = P h, S = h^T u + r, z = u - (S/2) K
// so it keeps the Joseph form's first-order insensitivity to errors in K (the short form P - K u^T does
// not) at O(d^2) cost. Only the lower triangle is computed and mirrored: P+ is exactly symmetric, which is
// the symmetrisation. (A stress test against a long-double reference — p0/r up to 1e16, near-collinear
// regressors — showed the same accuracy as evaluating the product (I - K h^T) P (I - K h^T)^T, at half
// the flops.)
// Writes u = P[n|n-1] h (the fixed-lag smoother needs it). work: kernel_work_size(d) doubles if D = 0.
template <int D>
CAUSAL_CORE_KERNEL UpdateResult joseph_update(int d_rt, double* __restrict x, double* __restrict p, const double* __restrict h,
                                  double y, double r, double* __restrict u, double* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  double* __restrict k = scratch.get();
  double* __restrict z = k + d;

  for (int i = 0; i < d; ++i) u[i] = 0.0;
  for (int j = 0; j < d; ++j) {
    const double hj = h[j];
    const double* pj = p + j * d;
    for (int i = 0; i < d; ++i) u[i] += pj[i] * hj;
  }
  double s = r, hx = 0.0;
  for (int i = 0; i < d; ++i) {
    s += h[i] * u[i];
    hx += h[i] * x[i];
  }
  const double e = y - hx;
  const double inv_s = 1.0 / s;
  const double half_s = 0.5 * s;
  for (int i = 0; i < d; ++i) {
    k[i] = u[i] * inv_s;
    z[i] = u[i] - half_s * k[i];
  }
  for (int j = 0; j < d; ++j) {
    const double kj = k[j], zj = z[j];
    double* pj = p + j * d;
    for (int i = j; i < d; ++i) pj[i] -= k[i] * zj + z[i] * kj;
  }
  for (int j = 0; j < d; ++j) {
    for (int i = j + 1; i < d; ++i) p[i * d + j] = p[j * d + i];
  }
  for (int i = 0; i < d; ++i) x[i] += k[i] * e;
  return {e, s};
}

// In-place Cholesky A = L L^T of an SPD matrix (column-major): the lower triangle of a becomes L (the upper
// triangle is left as it was), inv_diag[j] = 1 / L(j, j).
// Returns false if a pivot is not positive (not SPD to working precision).
template <int D>
CAUSAL_CORE_KERNEL bool cholesky(int d_rt, double* __restrict a, double* __restrict inv_diag) {
  const int d = D > 0 ? D : d_rt;
  for (int j = 0; j < d; ++j) {
    double* aj = a + j * d;
    for (int k = 0; k < j; ++k) {
      const double* ak = a + k * d;
      const double ljk = ak[j];
      for (int i = j; i < d; ++i) aj[i] -= ak[i] * ljk;
    }
    if (!(aj[j] > 0.0)) return false;
    const double ljj = std::sqrt(aj[j]);
    const double inv = 1.0 / ljj;
    aj[j] = ljj;
    inv_diag[j] = inv;
    for (int i = j + 1; i < d; ++i) aj[i] *= inv;
  }
  return true;
}

// Solves L L^T X = B in place for a d x d right-hand side B stored ROW-major in b (l, inv_diag from
// cholesky()). Row-oriented substitution: every operation is an axpy over a whole row of X, so the d
// right-hand sides proceed in parallel (vectorised) instead of as d serial substitution chains.
template <int D>
CAUSAL_CORE_KERNEL void cholesky_solve_rows(int d_rt, const double* __restrict l, const double* __restrict inv_diag,
                                double* __restrict b) {
  const int d = D > 0 ? D : d_rt;
  for (int j = 0; j < d; ++j) {  // forward: L Z = B
    double* bj = b + j * d;
    const double s = inv_diag[j];
    for (int c = 0; c < d; ++c) bj[c] *= s;
    for (int i = j + 1; i < d; ++i) {
      const double lij = l[j * d + i];  // L(i, j)
      double* bi = b + i * d;
      for (int c = 0; c < d; ++c) bi[c] -= lij * bj[c];
    }
  }
  for (int j = d - 1; j >= 0; --j) {  // backward: L^T X = Z
    double* bj = b + j * d;
    const double s = inv_diag[j];
    for (int c = 0; c < d; ++c) bj[c] *= s;
    for (int i = 0; i < j; ++i) {
      const double lji = l[i * d + j];  // L^T(i, j) = L(j, i)
      double* bi = b + i * d;
      for (int c = 0; c < d; ++c) bi[c] -= lji * bj[c];
    }
  }
}

// Rauch-Tung-Striebel backward step for x[n+1] = x[n] + w (A = I, Q = q I):
//   C_n    = P[n|n] (P[n|n] + Q)^{-1}              (P[n+1|n] = P[n|n] + Q)
//   x[n|N] = x[n|n] + C_n (x[n+1|N] - x[n|n])      (x[n+1|n] = x[n|n])
//   P[n|N] = P[n|n] + C_n (P[n+1|N] - P[n+1|n]) C_n^T
// (Rauch, Tung & Striebel 1965; Saerkkae, "Bayesian Filtering and Smoothing", 2013, Thm 8.2.)
// Split in two so callers can compute the gains of several samples back to back (they do not depend on the
// smoothed values, so their sqrt/divide latency chains overlap) before the sequential part.

// rts_gain: C_n (column-major, into c) from pf = P[n|n] by a Cholesky solve of P[n+1|n] C_n^T = P[n|n], never
// an explicit inverse. ~ 7/6 d^3 flops. Returns false if P[n+1|n] is not SPD to working precision.
template <int D>
CAUSAL_CORE_KERNEL bool rts_gain(int d_rt, double q, const double* __restrict pf, double* __restrict c,
                                 double* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  double* __restrict l = scratch.get();
  double* __restrict inv_diag = l + d * d;
  for (int j = 0; j < d; ++j) {
    for (int i = 0; i < d; ++i) {
      const double v = pf[j * d + i];
      l[j * d + i] = v + (i == j ? q : 0.0);
      c[j * d + i] = v;
    }
  }
  if (!cholesky<D>(d, l, inv_diag)) return false;
  // Right-hand side P[n|n] read row-major is the same array (symmetric); the solution X = C^T read row-major
  // is C column-major.
  cholesky_solve_rows<D>(d, l, inv_diag, c);
  return true;
}

// rts_apply: in: ps/xs = P[n+1|N], x[n+1|N]; out: P[n|N], x[n|N]. ~ 3/2 d^3 flops (lower triangle of the
// symmetric product, mirrored: the result is exactly symmetric).
template <int D>
CAUSAL_CORE_KERNEL void rts_apply(int d_rt, double q, const double* __restrict pf, const double* __restrict xf,
                                  const double* __restrict c, double* __restrict ps, double* __restrict xs,
                                  double* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  double* __restrict t = scratch.get();  // C (P[n+1|N] - P[n+1|n])
  double* __restrict dx = t + d * d;
  for (int i = 0; i < d; ++i) {
    dx[i] = xs[i] - xf[i];
    xs[i] = xf[i];
  }
  for (int k = 0; k < d; ++k) {
    const double dk = dx[k];
    const double* ck = c + k * d;
    for (int i = 0; i < d; ++i) xs[i] += ck[i] * dk;
  }
  // ps <- P[n+1|N] - P[n+1|n] = ps - pf - q I;  T = C ps (column j of T = sum_k C(:, k) ps(k, j))
  for (int i = 0; i < d * d; ++i) ps[i] -= pf[i];
  for (int i = 0; i < d; ++i) ps[i * d + i] -= q;
  for (int j = 0; j < d; ++j) {
    double* tj = t + j * d;
    const double* psj = ps + j * d;
    for (int i = 0; i < d; ++i) tj[i] = 0.0;
    for (int k = 0; k < d; ++k) {
      const double v = psj[k];
      const double* ck = c + k * d;
      for (int i = 0; i < d; ++i) tj[i] += ck[i] * v;
    }
  }
  // P[n|N] = pf + T C^T: column j = pf(:, j) + sum_k T(:, k) C(j, k); lower triangle, then mirrored.
  for (int j = 0; j < d; ++j) {
    double* psj = ps + j * d;
    const double* pfj = pf + j * d;
    for (int i = j; i < d; ++i) psj[i] = pfj[i];
    for (int k = 0; k < d; ++k) {
      const double v = c[k * d + j];
      const double* tk = t + k * d;
      for (int i = j; i < d; ++i) psj[i] += tk[i] * v;
    }
  }
  for (int j = 0; j < d; ++j) {
    for (int i = 0; i < j; ++i) ps[j * d + i] = ps[i * d + j];
  }
}

// Calls Op<D>::run(args...) with D = d for 1 <= d <= kMaxFixedDim and D = 0 (run-time size) otherwise.
template <template <int> class Op, typename... Args>
decltype(auto) dispatch_dim(int d, Args&&... args) {
  switch (d) {
    case 1: return Op<1>::run(std::forward<Args>(args)...);
    case 2: return Op<2>::run(std::forward<Args>(args)...);
    case 3: return Op<3>::run(std::forward<Args>(args)...);
    case 4: return Op<4>::run(std::forward<Args>(args)...);
    case 5: return Op<5>::run(std::forward<Args>(args)...);
    case 6: return Op<6>::run(std::forward<Args>(args)...);
    case 7: return Op<7>::run(std::forward<Args>(args)...);
    case 8: return Op<8>::run(std::forward<Args>(args)...);
    case 9: return Op<9>::run(std::forward<Args>(args)...);
    case 10: return Op<10>::run(std::forward<Args>(args)...);
    case 11: return Op<11>::run(std::forward<Args>(args)...);
    case 12: return Op<12>::run(std::forward<Args>(args)...);
    default: return Op<0>::run(std::forward<Args>(args)...);
  }
}

}  // namespace causal::detail
