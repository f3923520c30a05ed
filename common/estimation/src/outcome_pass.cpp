#include "outcome_pass.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels.hpp"
#include "segment_tracker.hpp"

namespace causal::detail {

std::vector<SampleStatus> classify_all(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                       const std::vector<bool>& discontinuity) {
  const int g = layout.channels();
  if (samples.cols() != g) {
    throw std::invalid_argument("samples must have one column per channel (" + std::to_string(g) + "), got " +
                                std::to_string(samples.cols()));
  }
  const Eigen::Index n = samples.rows();
  if (!discontinuity.empty() && static_cast<Eigen::Index>(discontinuity.size()) != n) {
    throw std::invalid_argument("discontinuity must be empty or have one flag per sample (" +
                                std::to_string(n) + "), got " + std::to_string(discontinuity.size()));
  }
  std::vector<SampleStatus> status(n);
  std::vector<double> row(g);
  int history = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int j = 0; j < g; ++j) row[j] = samples(i, j);
    status[i] = classify_sample(row.data(), g, layout.lag_order(), !discontinuity.empty() && discontinuity[i],
                                history);
  }
  return status;
}

std::vector<NoiseParams> expand_noise(const std::vector<NoiseParams>& noise, int channels) {
  std::vector<NoiseParams> out;
  if (noise.size() == 1) {
    out.assign(channels, noise.front());
  } else if (static_cast<int>(noise.size()) == channels) {
    out = noise;
  } else {
    throw std::invalid_argument("noise must have 1 or " + std::to_string(channels) + " (channels) entries, got " +
                                std::to_string(noise.size()));
  }
  for (int k = 0; k < channels; ++k) validate_noise_params(out[k], "noise[" + std::to_string(k) + "]");
  return out;
}

namespace {

template <int D>
struct ForwardOp {
  CAUSAL_CORE_CLONES static void run(GroupForward& job) {
    const LaneGroup& grp = *job.group;
    const int d = grp.d;
    const int count = grp.count;
    const Eigen::Index n_samples = job.samples->rows();
    const double* data = job.samples->data();
    // h(i, w)[n] = samples(n - lag, channel) = data[gather(i, w) + n] (column-major samples)
    std::vector<Eigen::Index> gather(static_cast<std::size_t>(d) * kLanes, 0);
    std::array<const double*, kLanes> y_col{};
    V4 q = splat(0.0), r = splat(1.0);
    std::vector<double> x(static_cast<std::size_t>(d) * kLanes, 0.0), h(x.size(), 0.0), u(x.size(), 0.0);
    std::vector<double> p(static_cast<std::size_t>(d) * d * kLanes, 0.0);
    for (int w = 0; w < kLanes; ++w) {
      const double p0 = w < count ? job.noise[w].p0 : 1.0;
      for (int i = 0; i < d; ++i) p[(static_cast<std::size_t>(i) * d + i) * kLanes + w] = p0;
    }
    for (int w = 0; w < count; ++w) {
      const int k = grp.outcome[w];
      const auto& regs = job.layout->regressors(k);
      for (int i = 0; i < d; ++i) {
        gather[static_cast<std::size_t>(i) * kLanes + w] =
            static_cast<Eigen::Index>(regs[i].channel) * n_samples - regs[i].lag;
      }
      y_col[w] = data + static_cast<Eigen::Index>(k) * n_samples;
      q[w] = job.noise[w].q;
      r[w] = job.noise[w].r;
    }
    std::vector<double> work(kernel_work_lanes(d) * kLanes);
    const std::vector<SampleStatus>& status = *job.status;
    const std::size_t per_sample = store_doubles_per_sample(d);
    V4* xv = lanes(x.data());
    V4* pv = lanes(p.data());
    // Outputs are column-major N x d per lane: writing one sample at a time would touch 2 d count cache lines
    // per sample, so kBlock samples are buffered (lane-interleaved) and then written column by column.
    constexpr Eigen::Index kBlock = 64;
    const bool want_x = std::any_of(job.x_cols.begin(), job.x_cols.end(), [](double* c) { return c; });
    const bool want_sd = std::any_of(job.sd_cols.begin(), job.sd_cols.end(), [](double* c) { return c; });
    std::vector<double> xbuf(want_x || want_sd ? kBlock * x.size() : 0), sdbuf(want_sd ? kBlock * x.size() : 0);
    Eigen::Index block_start = 0;
    auto flush = [&](Eigen::Index from, Eigen::Index to) {
      for (int w = 0; w < count; ++w) {
        for (int i = 0; i < d; ++i) {
          const std::size_t j = static_cast<std::size_t>(i) * kLanes + w;
          if (double* xc = job.x_cols[w]) {
            double* dst = xc + i * n_samples;
            for (Eigen::Index m = from; m < to; ++m) dst[m] = xbuf[static_cast<std::size_t>(m - from) * x.size() + j];
          }
          if (double* sc = job.sd_cols[w]) {
            double* dst = sc + i * n_samples;
            for (Eigen::Index m = from; m < to; ++m) dst[m] = sdbuf[static_cast<std::size_t>(m - from) * x.size() + j];
          }
        }
      }
    };
    for (Eigen::Index n = 0; n < n_samples; ++n) {
      if (n > 0) predict<D>(d, pv, q);
      if (status[n] == SampleStatus::Updated) {
        V4 y = splat(0.0);
        for (int w = 0; w < count; ++w) {
          y[w] = y_col[w][n];
          for (int i = 0; i < d; ++i) {
            const std::size_t j = static_cast<std::size_t>(i) * kLanes + w;
            h[j] = data[gather[j] + n];
          }
        }
        V4 e, s;
        joseph_update<D>(d, xv, pv, lanes(h.data()), y, r, lanes(u.data()), e, s, lanes(work.data()));
        ++job.updates;
        for (int w = 0; w < count; ++w) {
          if (job.likelihood) {
            job.sum_log_s[w] += std::log(s[w]);
            job.sum_e2_over_s[w] += e[w] * e[w] / s[w];
          }
          if (job.e_col[w]) job.e_col[w][n] = e[w];
          if (job.s_col[w]) job.s_col[w][n] = s[w];
        }
      }
      if (want_x || want_sd) {  // buffered, then written column by column (see flush)
        const std::size_t b = static_cast<std::size_t>(n - block_start);
        std::copy(x.begin(), x.end(), xbuf.begin() + b * x.size());
        if (want_sd) {
          V4* sd = lanes(sdbuf.data() + b * x.size());
          for (int i = 0; i < d; ++i) {
            const V4 v = pv[i * d + i];
            // Rounding can leave a variance <= 0 after many updates of an ill-scaled outcome: report 0 and
            // count it (the caller decides what to say) rather than a silent NaN from sqrt.
            for (int w = 0; w < kLanes; ++w) {
              if (v[w] > 0.0 || std::isnan(v[w])) {
                sd[i][w] = std::sqrt(v[w]);
              } else {
                sd[i][w] = 0.0;
                if (w < count) ++job.clamped_variances;
              }
            }
          }
        }
        if (n - block_start + 1 == kBlock || n + 1 == n_samples) {
          flush(block_start, n + 1);
          block_start = n + 1;
        }
      }
      if (job.store) {
        double* dst = job.store + static_cast<std::size_t>(n) * per_sample;
        std::copy(p.begin(), p.end(), dst);
        std::copy(x.begin(), x.end(), dst + p.size());
      }
    }
  }
};

// Backward pass: rts_gain / rts_apply (kernels.hpp) from the last sample down.
template <int D>
struct RtsOp {
  CAUSAL_CORE_CLONES static void run(const LaneGroup& grp, Eigen::Index n_samples,
                                     const std::array<double, kLanes>& q_lanes, const double* store,
                                     const std::array<double*, kLanes>& x_cols,
                                     const std::array<double*, kLanes>& sd_cols) {
    const int d = grp.d;
    if (n_samples == 0) return;
    const std::size_t np = static_cast<std::size_t>(d) * d * kLanes;
    const std::size_t per_sample = store_doubles_per_sample(d);
    const V4 q{q_lanes[0], q_lanes[1], q_lanes[2], q_lanes[3]};
    std::vector<double> ps(np), xs(static_cast<std::size_t>(d) * kLanes), work(kernel_work_lanes(d) * kLanes);
    // Outputs are buffered for kBlock samples (lane-interleaved) and written column by column, as in the
    // forward pass; samples come in decreasing order, so block slot b holds sample block_hi - b.
    constexpr Eigen::Index kBlock = 64;
    const std::size_t nx = xs.size();
    std::vector<double> xbuf(kBlock * nx), sdbuf(kBlock * nx);
    Eigen::Index block_hi = n_samples - 1;
    auto flush = [&](Eigen::Index lo) {
      for (int w = 0; w < grp.count; ++w) {
        for (int i = 0; i < d; ++i) {
          const std::size_t j = static_cast<std::size_t>(i) * kLanes + w;
          double* xc = x_cols[w] + i * n_samples;
          double* sc = sd_cols[w] + i * n_samples;
          for (Eigen::Index m = block_hi; m >= lo; --m) {
            const std::size_t b = static_cast<std::size_t>(block_hi - m) * nx + j;
            xc[m] = xbuf[b];
            sc[m] = sdbuf[b];
          }
        }
      }
    };
    auto emit = [&](Eigen::Index n) {
      const std::size_t b = static_cast<std::size_t>(block_hi - n) * nx;
      std::copy(xs.begin(), xs.end(), xbuf.begin() + b);
      V4* sd = lanes(sdbuf.data() + b);
      const V4* p = lanes(ps.data());
      for (int i = 0; i < d; ++i) {
        const V4 v = p[i * d + i];
        for (int w = 0; w < kLanes; ++w) sd[i][w] = std::sqrt(std::max(v[w], 0.0));
      }
      if (block_hi - n + 1 == kBlock || n == 0) {
        flush(n);
        block_hi = n - 1;
      }
    };
    const Eigen::Index last = n_samples - 1;
    const double* src = store + static_cast<std::size_t>(last) * per_sample;
    std::copy(src, src + np, ps.begin());
    std::copy(src + np, src + per_sample, xs.begin());
    emit(last);
    // Gains first for a chunk of samples (independent of the smoothed values), then the sequential part.
    constexpr Eigen::Index kChunk = 8;
    std::vector<double> gains(static_cast<std::size_t>(kChunk) * np);
    std::array<bool, kChunk> ok{};
    for (Eigen::Index hi = last - 1; hi >= 0; hi -= kChunk) {
      const Eigen::Index lo = std::max<Eigen::Index>(0, hi - kChunk + 1);
      for (Eigen::Index n = hi; n >= lo; --n) {
        const double* pf = store + static_cast<std::size_t>(n) * per_sample;
        ok[hi - n] = rts_gain<D>(d, q, lanes(pf), lanes(gains.data() + (hi - n) * np), lanes(work.data()));
      }
      for (Eigen::Index n = hi; n >= lo; --n) {
        const double* pf = store + static_cast<std::size_t>(n) * per_sample;
        if (ok[hi - n]) {
          rts_apply<D>(d, q, lanes(pf), lanes(pf + np), lanes(gains.data() + (hi - n) * np), lanes(ps.data()),
                       lanes(xs.data()), lanes(work.data()));
        } else {
          // P[n+1|n] = P[n|n] + q I not SPD (cannot happen for p0 > 0, r > 0 short of overflow): fall back to
          // the filtered values rather than emit garbage.
          std::copy(pf, pf + np, ps.begin());
          std::copy(pf + np, pf + per_sample, xs.begin());
        }
        emit(n);
      }
    }
  }
};

}  // namespace

void run_group_forward(GroupForward& job) { dispatch_dim<ForwardOp>(job.group->d, job); }

void run_group_rts(const LaneGroup& group, Eigen::Index n_samples, const std::array<double, kLanes>& q,
                   const double* store, const std::array<double*, kLanes>& x_cols,
                   const std::array<double*, kLanes>& sd_cols) {
  dispatch_dim<RtsOp>(group.d, group, n_samples, q, store, x_cols, sd_cols);
}

}  // namespace causal::detail
