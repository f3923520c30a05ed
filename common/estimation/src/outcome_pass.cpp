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
  CAUSAL_CORE_CLONES static void run(OutcomeForward& job) {
    const SvarLayout& layout = *job.layout;
    const int d = layout.factor_count(job.k);
    const Eigen::Index n_samples = job.samples->rows();
    const double* data = job.samples->data();
    // h_i[n] = samples(n - lag_i, channel_i) = data[gather_i + n] (column-major samples)
    std::vector<Eigen::Index> gather(d);
    for (int i = 0; i < d; ++i) {
      const Regressor& reg = layout.regressors(job.k)[i];
      gather[i] = static_cast<Eigen::Index>(reg.channel) * n_samples - reg.lag;
    }
    const std::size_t dd = static_cast<std::size_t>(d) * d;
    std::vector<double> x(d, 0.0), p(dd, 0.0), h(d), u(d);
    std::vector<double> work(kernel_work_size(d));
    for (int i = 0; i < d; ++i) p[i * d + i] = job.noise.p0;
    const std::vector<SampleStatus>& status = *job.status;
    const double* y = data + job.k * n_samples;
    for (Eigen::Index n = 0; n < n_samples; ++n) {
      if (n > 0) predict<D>(d, p.data(), job.noise.q);
      if (status[n] == SampleStatus::Updated) {
        for (int i = 0; i < d; ++i) h[i] = data[gather[i] + n];
        const UpdateResult res =
            joseph_update<D>(d, x.data(), p.data(), h.data(), y[n], job.noise.r, u.data(), work.data());
        job.sum_log_s += std::log(res.s);
        job.sum_e2_over_s += res.e * res.e / res.s;
        ++job.updates;
        if (job.e_col) job.e_col[n] = res.e;
        if (job.s_col) job.s_col[n] = res.s;
      }
      if (job.x_cols) {
        for (int i = 0; i < d; ++i) job.x_cols[i * n_samples + n] = x[i];
      }
      if (job.sd_cols) {
        for (int i = 0; i < d; ++i) job.sd_cols[i * n_samples + n] = std::sqrt(p[i * d + i]);
      }
      if (job.p_store) std::copy(p.begin(), p.end(), job.p_store + n * static_cast<Eigen::Index>(dd));
    }
  }
};

// Backward pass: rts_step (kernels.hpp) from the last sample down, reading P[n|n] from p_store and x[n|n]
// from x_cols, writing x[n|N] back into x_cols.
template <int D>
struct RtsOp {
  CAUSAL_CORE_CLONES static void run(int d, Eigen::Index n_samples, double q, const double* p_store, double* x_cols,
                  double* sd_cols) {
    if (n_samples == 0 || d == 0) return;
    const std::size_t dd = static_cast<std::size_t>(d) * d;
    std::vector<double> ps(dd), xs(d), xf(d), work(kernel_work_size(d));
    const Eigen::Index last = n_samples - 1;
    std::copy(p_store + last * static_cast<Eigen::Index>(dd), p_store + n_samples * static_cast<Eigen::Index>(dd),
              ps.begin());
    for (int i = 0; i < d; ++i) {
      xs[i] = x_cols[i * n_samples + last];
      sd_cols[i * n_samples + last] = std::sqrt(ps[i * d + i]);
    }
    for (Eigen::Index n = last - 1; n >= 0; --n) {
      const double* pf = p_store + n * static_cast<Eigen::Index>(dd);
      for (int i = 0; i < d; ++i) xf[i] = x_cols[i * n_samples + n];
      if (!rts_step<D>(d, q, pf, xf.data(), ps.data(), xs.data(), work.data())) {
        // P[n+1|n] = P[n|n] + q I lost positive definiteness (cannot happen for p0 > 0, r > 0 short of
        // overflow): fall back to the filtered values rather than emit garbage.
        std::copy(pf, pf + dd, ps.begin());
        std::copy(xf.begin(), xf.end(), xs.begin());
      }
      for (int i = 0; i < d; ++i) {
        x_cols[i * n_samples + n] = xs[i];
        sd_cols[i * n_samples + n] = std::sqrt(std::max(ps[i * d + i], 0.0));
      }
    }
  }
};

}  // namespace

void run_outcome_forward(OutcomeForward& job) {
  dispatch_dim<ForwardOp>(job.layout->factor_count(job.k), job);
}

void run_outcome_rts(int d, Eigen::Index n_samples, double q, const double* p_store, double* x_cols,
                     double* sd_cols) {
  dispatch_dim<RtsOp>(d, d, n_samples, q, p_store, x_cols, sd_cols);
}

}  // namespace causal::detail
