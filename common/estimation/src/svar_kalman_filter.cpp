#include "causal/svar_kalman_filter.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "kernels.hpp"
#include "segment_tracker.hpp"

namespace causal {

const char* to_string(SampleStatus status) {
  switch (status) {
    case SampleStatus::Updated: return "updated";
    case SampleStatus::WarmUp: return "warm-up";
    case SampleStatus::RejectedNonFinite: return "rejected-non-finite";
  }
  return "unknown";
}

// Binds the per-outcome function pointers to the fixed-size kernels of dimension D.
template <int D>
struct SvarKalmanFilter::Select {
  CAUSAL_CORE_CLONES static void update(SvarKalmanFilter& f, int k, double y) {
    const int o = f.x_off_[k];
    const detail::UpdateResult res =
        detail::joseph_update<D>(f.dim_[k], f.x_.data() + o, f.p_.data() + f.p_off_[k], f.h_.data() + o, y,
                                 f.noise_[k].r, f.u_.data() + o, f.work_.data());
    f.e_[k] = res.e;
    f.s_[k] = res.s;
  }
  static void run(SvarKalmanFilter& f, int k) {
    f.update_fn_[k] = &update;
  }
};

SvarKalmanFilter::SvarKalmanFilter(const SvarLayout& layout, std::vector<NoiseParams> noise)
    : layout_(layout), g_(layout.channels()), m_(layout.lag_order()) {
  if (noise.size() == 1) {
    noise_.assign(g_, noise.front());
  } else if (static_cast<int>(noise.size()) == g_) {
    noise_ = std::move(noise);
  } else {
    throw std::invalid_argument("SvarKalmanFilter: noise must have 1 or " + std::to_string(g_) +
                                " (channels) entries, got " + std::to_string(noise.size()));
  }
  for (int k = 0; k < g_; ++k) validate_noise_params(noise_[k], "noise[" + std::to_string(k) + "]");

  const int f = layout_.total_factors();
  dim_.resize(g_);
  x_off_.resize(g_);
  p_off_.resize(g_);
  update_fn_.resize(g_);
  gather_.resize(f);
  int p_total = 0;
  for (int k = 0; k < g_; ++k) {
    dim_[k] = layout_.factor_count(k);
    x_off_[k] = layout_.offset(k);
    p_off_[k] = p_total;
    p_total += dim_[k] * dim_[k];
    const auto& regs = layout_.regressors(k);
    for (int i = 0; i < dim_[k]; ++i) gather_[x_off_[k] + i] = regs[i].lag * g_ + regs[i].channel;
    detail::dispatch_dim<Select>(dim_[k], *this, k);
  }
  x_.resize(f);
  p_.resize(p_total);
  window_.assign(static_cast<std::size_t>(m_ + 1) * g_, 0.0);
  h_.assign(f, 0.0);
  u_.assign(f, 0.0);
  e_.resize(g_);
  s_.resize(g_);
  work_.resize(detail::kernel_work_size(layout_.max_factor_count()));
  reset();
}

void SvarKalmanFilter::reset() {
  std::fill(x_.begin(), x_.end(), 0.0);
  std::fill(p_.begin(), p_.end(), 0.0);
  for (int k = 0; k < g_; ++k) {
    Eigen::Map<Eigen::MatrixXd> P(p_.data() + p_off_[k], dim_[k], dim_[k]);
    P.diagonal().setConstant(noise_[k].p0);
  }
  std::fill(e_.begin(), e_.end(), std::numeric_limits<double>::quiet_NaN());
  std::fill(s_.begin(), s_.end(), std::numeric_limits<double>::quiet_NaN());
  history_ = 0;
  steps_ = 0;
  counters_ = FilterCounters{};
}

SampleStatus SvarKalmanFilter::step(const double* y, bool discontinuity) {
  if (steps_ > 0) {
    // P += q I (time passes for every sample, usable or not)
    for (int k = 0; k < g_; ++k) {
      double* p = p_.data() + p_off_[k];
      const int d = dim_[k];
      const double q = noise_[k].q;
      for (int i = 0; i < d; ++i) p[i * d + i] += q;
    }
  }
  ++steps_;
  const SampleStatus status = detail::classify_sample(y, g_, m_, discontinuity, history_);
  if (status == SampleStatus::RejectedNonFinite) {
    ++counters_.rejected_non_finite;
    return status;
  }
  // Shift the lag window by one sample (row l holds y[n-l]) and put y in row 0.
  std::memmove(window_.data() + g_, window_.data(), sizeof(double) * static_cast<std::size_t>(m_ * g_));
  std::memcpy(window_.data(), y, sizeof(double) * static_cast<std::size_t>(g_));
  if (status == SampleStatus::WarmUp) {
    ++counters_.warm_up;
    return status;
  }
  const int f = static_cast<int>(x_.size());
  for (int i = 0; i < f; ++i) h_[i] = window_[gather_[i]];
  for (int k = 0; k < g_; ++k) update_fn_[k](*this, k, y[k]);
  ++counters_.updated;
  return status;
}

double SvarKalmanFilter::last_innovation(int k) const { return e_.at(k); }

double SvarKalmanFilter::last_innovation_variance(int k) const { return s_.at(k); }

Eigen::VectorXd SvarKalmanFilter::estimate(int k) const {
  return Eigen::Map<const Eigen::VectorXd>(x_.data() + x_off_.at(k), dim_[k]);
}

Eigen::MatrixXd SvarKalmanFilter::covariance(int k) const {
  return Eigen::Map<const Eigen::MatrixXd>(p_.data() + p_off_.at(k), dim_[k], dim_[k]);
}

void SvarKalmanFilter::estimates(double* out) const { std::copy(x_.begin(), x_.end(), out); }

void SvarKalmanFilter::std_devs(double* out) const {
  for (int k = 0; k < g_; ++k) {
    const double* p = p_.data() + p_off_[k];
    const int d = dim_[k];
    for (int i = 0; i < d; ++i) out[x_off_[k] + i] = std::sqrt(p[i * d + i]);
  }
}

const NoiseParams& SvarKalmanFilter::noise(int k) const { return noise_.at(k); }

void SvarKalmanFilter::set_noise(int k, const NoiseParams& noise) {
  validate_noise_params(noise, "set_noise(" + std::to_string(k) + ")");
  noise_.at(k) = noise;
}

}  // namespace causal
