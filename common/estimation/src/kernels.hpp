// Kalman kernels for FOUR independent outcomes at once ("lanes"): outcomes of equal state dimension d are
// grouped by four and every scalar operation of the per-outcome algorithm becomes one 4-wide vector operation
// (GCC/Clang vector extension, AVX2 or 2 x SSE2). Unused lanes carry a harmless dummy model (h = 0, y = 0,
// r = 1, q = 0). Storage is "structure of arrays": element i of a vector is V4 v[i] (lane w = v[i][w]);
// element (i, j) of a d x d matrix (column-major) is V4 m[j * d + i].
//
// Kernels are templated on D = d for 1 <= d <= kMaxFixedDim (compile-time trip counts, scratch on the stack);
// D = 0 means "d known at run time" and uses caller-owned scratch, so nothing allocates per step.
// Plain loops over V4 rather than Eigen expressions: small-matrix kernels like these compile to much better
// code this way (and far faster: fixed-size Eigen LLT/product instantiations for 12 sizes took minutes).
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>

namespace causal::estimation::detail {

constexpr int kLanes = 4;
// 14 covers G = 8, M = 1 (the eight-sensor model; 1.4-1.5x faster than the run-time-size kernels, measured).
constexpr int kMaxFixedDim = 14;

// 4 doubles; may alias double and needs only 8-byte alignment, so it can view std::vector<double> storage.
typedef double V4 __attribute__((vector_size(32), aligned(8), may_alias));

inline V4 splat(double a) { return V4{a, a, a, a}; }
inline V4* lanes(double* p) { return reinterpret_cast<V4*>(p); }
inline const V4* lanes(const double* p) { return reinterpret_cast<const V4*>(p); }

// Entry points that run the kernels (the kernels themselves are force-inlined into them) are compiled three
// times on x86-64 GCC: baseline (2 x SSE2), x86-64-v3 (AVX2 + FMA) and x86-64-v4 (AVX-512 F/BW/DQ/VL: the same
// 4-wide vectors, but 32 vector registers instead of 16, so the d = 6..12 kernels spill less); the loader picks
// the best clone the CPU supports (function multi-versioning, an ifunc resolved once at start-up): portable
// binaries that still use the widest vectors available. FMA contraction (-ffp-contract=fast) can change the
// last bits between the baseline and the v3/v4 clones; on one machine the same clone is always chosen, so
// runs and checkpoints repeat bit for bit there (tests compare with independent references to 1e-14).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(CAUSAL_CORE_NO_CLONES)
#define CAUSAL_CORE_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CAUSAL_CORE_CLONES
#endif
#define CAUSAL_CORE_KERNEL __attribute__((always_inline)) inline

// V4 elements of scratch a D = 0 kernel needs for dimension d (covers every kernel below).
inline std::size_t kernel_work_lanes(int d) { return static_cast<std::size_t>(3 * d * d + 4 * d); }

// Stack scratch for fixed D, caller scratch for D = 0.
template <int D>
struct Scratch {
  V4 buf[3 * D * D + 4 * D];
  explicit Scratch(V4* /*unused*/) {}
  V4* get() { return buf; }
};
template <>
struct Scratch<0> {
  V4* ptr;
  explicit Scratch(V4* work) : ptr(work) {}
  V4* get() { return ptr; }
};

// Time update of the random walk x[n+1] = x[n] + w, w ~ N(0, q I): x unchanged, P += q I.
template <int D>
CAUSAL_CORE_KERNEL void predict(int d_rt, V4* p, V4 q) {
  const int d = D > 0 ? D : d_rt;
  for (int i = 0; i < d; ++i) p[i * d + i] += q;
}

// Scalar measurement update y = h^T x + eps, eps ~ N(0, r), covariance in Joseph form
//   P+ = (I - K h^T) P (I - K h^T)^T + r K K^T            (Bucy & Joseph 1968; Simon, "Optimal State
//                                                          Estimation", 2006, eq. 5.19)
// For a scalar measurement it expands exactly, for ANY gain K, into the symmetric rank-2 update
//   P+ = P - K u^T - u K^T + S K K^T = P - K z^T - z K^T,   u = P h, S = h^T u + r, z = u - (S/2) K
// so it keeps the Joseph form's first-order insensitivity to errors in K (the short form P - K u^T does
// not) at O(d^2) cost. Only the lower triangle is computed and then mirrored: P+ is exactly symmetric
// (that is the symmetrisation). A stress test against a long-double reference (p0/r up to 1e16,
// near-collinear regressors) showed the same accuracy as evaluating the product form, at half the flops.
// Outputs u = P[n|n-1] h (the fixed-lag smoother needs it), e = y - h^T x[n|n-1] and S.
template <int D>
CAUSAL_CORE_KERNEL void joseph_update(int d_rt, V4* __restrict x, V4* __restrict p, const V4* __restrict h,
                                      V4 y, V4 r, V4* __restrict u, V4& e_out, V4& s_out, V4* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  V4* __restrict k = scratch.get();
  V4* __restrict z = k + d;

  for (int i = 0; i < d; ++i) u[i] = splat(0.0);
  for (int j = 0; j < d; ++j) {
    const V4 hj = h[j];
    const V4* pj = p + j * d;
    for (int i = 0; i < d; ++i) u[i] += pj[i] * hj;
  }
  V4 s = r, hx = splat(0.0);
  for (int i = 0; i < d; ++i) {
    s += h[i] * u[i];
    hx += h[i] * x[i];
  }
  const V4 e = y - hx;
  const V4 inv_s = 1.0 / s;
  const V4 half_s = 0.5 * s;
  for (int i = 0; i < d; ++i) {
    k[i] = u[i] * inv_s;
    z[i] = u[i] - half_s * k[i];
  }
  for (int j = 0; j < d; ++j) {
    const V4 kj = k[j], zj = z[j];
    V4* pj = p + j * d;
    for (int i = j; i < d; ++i) pj[i] -= k[i] * zj + z[i] * kj;
  }
  for (int j = 0; j < d; ++j) {
    for (int i = j + 1; i < d; ++i) p[i * d + j] = p[j * d + i];
  }
  for (int i = 0; i < d; ++i) x[i] += k[i] * e;
  e_out = e;
  s_out = s;
}

// Cholesky A = L L^T of SPD matrices (column-major), written to l (lower triangle; the upper triangle of l
// is not touched), inv_diag[j] = 1 / L(j, j). Columns are accumulated in tmp (d elements) so no store can
// alias a load. Returns false if any lane has a non-positive pivot (not SPD to working precision).
template <int D>
CAUSAL_CORE_KERNEL bool cholesky(int d_rt, const V4* __restrict a, V4* __restrict l, V4* __restrict inv_diag,
                                 V4* __restrict tmp) {
  const int d = D > 0 ? D : d_rt;
  for (int j = 0; j < d; ++j) {
    for (int i = j; i < d; ++i) tmp[i] = a[j * d + i];
    for (int k = 0; k < j; ++k) {
      const V4* lk = l + k * d;
      const V4 ljk = lk[j];
      for (int i = j; i < d; ++i) tmp[i] -= lk[i] * ljk;
    }
    const V4 pivot = tmp[j];
    bool spd = true;
    for (int w = 0; w < kLanes; ++w) spd &= pivot[w] > 0.0;  // also false for NaN
    if (!spd) return false;
    V4 ljj;
    for (int w = 0; w < kLanes; ++w) ljj[w] = std::sqrt(pivot[w]);
    const V4 inv = 1.0 / ljj;
    V4* lj = l + j * d;
    lj[j] = ljj;
    inv_diag[j] = inv;
    for (int i = j + 1; i < d; ++i) lj[i] = tmp[i] * inv;
  }
  return true;
}

// Solves L L^T X = B in place for a d x d right-hand side stored ROW-major in b. Row-oriented substitution:
// every operation is an axpy over a whole row, so the d right-hand sides run in parallel. tmp: d elements.
template <int D>
CAUSAL_CORE_KERNEL void cholesky_solve_rows(int d_rt, const V4* __restrict l, const V4* __restrict inv_diag,
                                            V4* __restrict b, V4* __restrict tmp) {
  const int d = D > 0 ? D : d_rt;
  for (int j = 0; j < d; ++j) {  // forward: L Z = B
    V4* bj = b + j * d;
    const V4 s = inv_diag[j];
    for (int c = 0; c < d; ++c) {
      tmp[c] = bj[c] * s;
      bj[c] = tmp[c];
    }
    for (int i = j + 1; i < d; ++i) {
      const V4 lij = l[j * d + i];  // L(i, j)
      V4* bi = b + i * d;
      for (int c = 0; c < d; ++c) bi[c] -= lij * tmp[c];
    }
  }
  for (int j = d - 1; j >= 0; --j) {  // backward: L^T X = Z
    V4* bj = b + j * d;
    const V4 s = inv_diag[j];
    for (int c = 0; c < d; ++c) {
      tmp[c] = bj[c] * s;
      bj[c] = tmp[c];
    }
    for (int i = 0; i < j; ++i) {
      const V4 lji = l[i * d + j];  // L^T(i, j) = L(j, i)
      V4* bi = b + i * d;
      for (int c = 0; c < d; ++c) bi[c] -= lji * tmp[c];
    }
  }
}

// Rauch-Tung-Striebel backward step for x[n+1] = x[n] + w (A = I, Q = q I):
//   C_n    = P[n|n] (P[n|n] + Q)^{-1}              (P[n+1|n] = P[n|n] + Q)
//   x[n|N] = x[n|n] + C_n (x[n+1|N] - x[n|n])      (x[n+1|n] = x[n|n])
//   P[n|N] = P[n|n] + C_n (P[n+1|N] - P[n+1|n]) C_n^T
// (Rauch, Tung & Striebel 1965; Saerkkae, "Bayesian Filtering and Smoothing", 2013, Thm 8.2.)
// Split in two: the gains C_n depend only on P[n|n], so callers compute several of them back to back (their
// sqrt/divide latency chains then overlap) before the sequential part. ~ 3.2 d^3 flops in total.

// rts_gain: C_n, column-major into c, from a Cholesky solve P[n+1|n] C_n^T = P[n|n], never an explicit
// inverse. Returns false if P[n+1|n] is not SPD to working precision in some lane.
template <int D>
CAUSAL_CORE_KERNEL bool rts_gain(int d_rt, V4 q, const V4* __restrict pf, V4* __restrict c, V4* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  V4* __restrict a = scratch.get();  // P[n+1|n]
  V4* __restrict l = a + d * d;      // its Cholesky factor
  V4* __restrict inv_diag = l + d * d;
  V4* __restrict tmp = inv_diag + d;
  for (int j = 0; j < d; ++j) {
    for (int i = 0; i < d; ++i) {
      const V4 v = pf[j * d + i];
      a[j * d + i] = i == j ? v + q : v;
      c[j * d + i] = v;
    }
  }
  if (!cholesky<D>(d, a, l, inv_diag, tmp)) return false;
  // Right-hand side P[n|n] read row-major is the same array (symmetric); the solution X = C^T read row-major
  // is C column-major.
  cholesky_solve_rows<D>(d, l, inv_diag, c, tmp);
  return true;
}

// rts_apply: in: ps/xs = P[n+1|N], x[n+1|N]; out: P[n|N], x[n|N] (P exactly symmetric: lower triangle
// computed, then mirrored). pf = P[n|n], xf = x[n|n], c = C_n from rts_gain.
template <int D>
CAUSAL_CORE_KERNEL void rts_apply(int d_rt, V4 q, const V4* __restrict pf, const V4* __restrict xf,
                                  const V4* __restrict c, V4* __restrict ps, V4* __restrict xs, V4* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  V4* __restrict t = scratch.get();  // C (P[n+1|N] - P[n+1|n])
  V4* __restrict dx = t + d * d;
  // x[n|N] = xf + C (xs - xf)
  for (int i = 0; i < d; ++i) {
    dx[i] = xs[i] - xf[i];
    xs[i] = xf[i];
  }
  for (int k = 0; k < d; ++k) {
    const V4 dk = dx[k];
    const V4* ck = c + k * d;
    for (int i = 0; i < d; ++i) xs[i] += ck[i] * dk;
  }
  // ps <- P[n+1|N] - P[n+1|n] = ps - pf - q I;  T = C ps (column j of T = sum_k C(:, k) ps(k, j))
  for (int i = 0; i < d * d; ++i) ps[i] -= pf[i];
  for (int i = 0; i < d; ++i) ps[i * d + i] -= q;
  for (int j = 0; j < d; ++j) {
    V4* tj = t + j * d;
    const V4* psj = ps + j * d;
    for (int i = 0; i < d; ++i) tj[i] = splat(0.0);
    for (int k = 0; k < d; ++k) {
      const V4 v = psj[k];
      const V4* ck = c + k * d;
      for (int i = 0; i < d; ++i) tj[i] += ck[i] * v;
    }
  }
  // P[n|N] = pf + T C^T: column j = pf(:, j) + sum_k T(:, k) C(j, k); lower triangle, then mirrored.
  for (int j = 0; j < d; ++j) {
    V4* psj = ps + j * d;
    const V4* pfj = pf + j * d;
    for (int i = j; i < d; ++i) psj[i] = pfj[i];
    for (int k = 0; k < d; ++k) {
      const V4 v = c[k * d + j];
      const V4* tk = t + k * d;
      for (int i = j; i < d; ++i) psj[i] += tk[i] * v;
    }
  }
  for (int j = 0; j < d; ++j) {
    for (int i = 0; i < j; ++i) ps[j * d + i] = ps[i * d + j];
  }
}

// Fixed-lag smoother update of one lagged state x[n-i] (see fixed_lag_smoother.hpp):
//   g = P[n-i,n] h / S;  x[n-i] += g e;  P[n-i,n] -= g u^T;  var[n-i] -= S g.^2
template <int D>
CAUSAL_CORE_KERNEL void lag_update(int d_rt, const V4* __restrict h, const V4* __restrict u, V4 e, V4 s,
                                   V4 inv_s, V4* __restrict pc, V4* __restrict x, V4* __restrict var,
                                   V4* work) {
  const int d = D > 0 ? D : d_rt;
  Scratch<D> scratch(work);
  V4* __restrict g = scratch.get();
  for (int i = 0; i < d; ++i) g[i] = splat(0.0);
  for (int j = 0; j < d; ++j) {
    const V4 hj = h[j];
    const V4* pj = pc + j * d;
    for (int i = 0; i < d; ++i) g[i] += pj[i] * hj;
  }
  for (int i = 0; i < d; ++i) {
    g[i] *= inv_s;
    x[i] += g[i] * e;
    var[i] -= s * g[i] * g[i];
  }
  for (int j = 0; j < d; ++j) {
    const V4 uj = u[j];
    V4* pj = pc + j * d;
    for (int i = 0; i < d; ++i) pj[i] -= g[i] * uj;
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
    case 13: return Op<13>::run(std::forward<Args>(args)...);
    case 14: return Op<14>::run(std::forward<Args>(args)...);
    default: return Op<0>::run(std::forward<Args>(args)...);
  }
}

}  // namespace causal::estimation::detail
