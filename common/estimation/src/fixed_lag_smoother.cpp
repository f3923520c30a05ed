#include "causal/fixed_lag_smoother.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels.hpp"

namespace causal {

// Lag update of outcome k with the filter's last regressors h, u = P[n|n-1] h, innovation e and variance S
// (equations in the header), for every lagged slot i = 1..active.
template <int D>
struct FixedLagSmoother::Select {
  CAUSAL_CORE_CLONES static void update(FixedLagSmoother& s, int k) {
    const SvarKalmanFilter& f = s.filter_;
    const int d = D > 0 ? D : s.dim_[k];
    const int xo = s.x_off_[k];
    const double* __restrict h = f.h_.data() + xo;
    const double* __restrict u = f.u_.data() + xo;
    detail::Scratch<D> scratch(s.work_.data());
    double* __restrict g = scratch.get();
    const double e = f.e_[k];
    const double sv = f.s_[k];
    const double inv_s = 1.0 / sv;
    double* xs = s.xs_.data() + static_cast<std::size_t>(s.lag_) * xo;
    double* pc = s.pc_.data() + static_cast<std::size_t>(s.lag_) * s.p_off_[k];
    double* var = s.var_.data() + static_cast<std::size_t>(s.lag_) * xo;
    for (int slot = 1; slot <= s.active_; ++slot) {
      const int pos = s.slot_pos(slot);
      double* __restrict p = pc + static_cast<std::size_t>(pos) * d * d;
      double* __restrict x = xs + static_cast<std::size_t>(pos) * d;
      double* __restrict v = var + static_cast<std::size_t>(pos) * d;
      for (int i = 0; i < d; ++i) g[i] = 0.0;
      for (int j = 0; j < d; ++j) {  // g = P[n-i,n] h / S
        const double hj = h[j];
        const double* pj = p + j * d;
        for (int i = 0; i < d; ++i) g[i] += pj[i] * hj;
      }
      for (int i = 0; i < d; ++i) {
        g[i] *= inv_s;
        x[i] += g[i] * e;
        v[i] -= sv * g[i] * g[i];
      }
      for (int j = 0; j < d; ++j) {  // P[n-i,n] -= g u^T
        const double uj = u[j];
        double* pj = p + j * d;
        for (int i = 0; i < d; ++i) pj[i] -= g[i] * uj;
      }
    }
  }
  static void run(FixedLagSmoother& s, int k) { s.update_fn_[k] = &update; }
};

FixedLagSmoother::FixedLagSmoother(const SvarLayout& layout, std::vector<NoiseParams> noise, int lag)
    : filter_(layout, std::move(noise)), lag_(lag), g_(layout.channels()) {
  if (lag < 0) throw std::invalid_argument("FixedLagSmoother: lag must be >= 0, got " + std::to_string(lag));
  dim_.resize(g_);
  x_off_.resize(g_);
  p_off_.resize(g_);
  update_fn_.resize(g_);
  int p_total = 0;
  for (int k = 0; k < g_; ++k) {
    dim_[k] = layout.factor_count(k);
    x_off_[k] = layout.offset(k);
    p_off_[k] = p_total;
    p_total += dim_[k] * dim_[k];
    detail::dispatch_dim<Select>(dim_[k], *this, k);
  }
  const auto l = static_cast<std::size_t>(lag_);
  xs_.assign(l * layout.total_factors(), 0.0);
  var_.assign(l * layout.total_factors(), 0.0);
  pc_.assign(l * p_total, 0.0);
  work_.assign(detail::kernel_work_size(layout.max_factor_count()), 0.0);
}

void FixedLagSmoother::reset() {
  filter_.reset();
  head_ = 0;
  active_ = 0;
  next_release_ = 0;
  last_status_ = SampleStatus::WarmUp;
}

// Augmented prediction: x[n-1|n-1] becomes lag 1, its covariance is both P[n-1,n-1] and the cross-covariance
// P[n-1,n] (x[n] = x[n-1] + w with w independent of the past).
void FixedLagSmoother::shift_in_filter_state() {
  if (lag_ == 0) return;
  head_ = (head_ + 1) % lag_;
  active_ = std::min(active_ + 1, lag_);
  for (int k = 0; k < g_; ++k) {
    const int d = dim_[k];
    const std::size_t xo = static_cast<std::size_t>(lag_) * x_off_[k] + static_cast<std::size_t>(head_) * d;
    const std::size_t po =
        static_cast<std::size_t>(lag_) * p_off_[k] + static_cast<std::size_t>(head_) * d * d;
    const double* fx = filter_.x_.data() + x_off_[k];
    const double* fp = filter_.p_.data() + filter_.p_off_[k];
    std::copy(fx, fx + d, xs_.data() + xo);
    std::copy(fp, fp + d * d, pc_.data() + po);
    for (int i = 0; i < d; ++i) var_[xo + i] = fp[i * d + i];
  }
}

void FixedLagSmoother::write_lag(int i, double* estimates, double* std_devs) const {
  if (i == 0) {
    filter_.estimates(estimates);
    filter_.std_devs(std_devs);
    return;
  }
  const int pos = slot_pos(i);
  for (int k = 0; k < g_; ++k) {
    const int d = dim_[k];
    const std::size_t xo = static_cast<std::size_t>(lag_) * x_off_[k] + static_cast<std::size_t>(pos) * d;
    for (int j = 0; j < d; ++j) {
      estimates[x_off_[k] + j] = xs_[xo + j];
      std_devs[x_off_[k] + j] = std::sqrt(std::max(var_[xo + j], 0.0));
    }
  }
}

bool FixedLagSmoother::step_into(const double* y, bool discontinuity, std::uint64_t* index, double* estimates,
                                 double* std_devs) {
  if (filter_.samples_seen() > 0) shift_in_filter_state();
  last_status_ = filter_.step(y, discontinuity);
  if (last_status_ == SampleStatus::Updated) {
    for (int k = 0; k < g_; ++k) update_fn_[k](*this, k);
  }
  const std::uint64_t n = filter_.samples_seen() - 1;
  if (n < static_cast<std::uint64_t>(lag_)) return false;
  const std::uint64_t release = n - static_cast<std::uint64_t>(lag_);
  if (release < next_release_) return false;  // already flushed
  next_release_ = release + 1;
  *index = release;
  write_lag(lag_, estimates, std_devs);
  return true;
}

std::optional<SmoothedSample> FixedLagSmoother::step(const double* y, bool discontinuity) {
  const int f = filter_.layout().total_factors();
  SmoothedSample out{0, Eigen::VectorXd(f), Eigen::VectorXd(f)};
  if (!step_into(y, discontinuity, &out.index, out.estimates.data(), out.std_devs.data())) return std::nullopt;
  return out;
}

std::vector<SmoothedSample> FixedLagSmoother::flush() {
  std::vector<SmoothedSample> out;
  const std::uint64_t seen = filter_.samples_seen();
  const int f = filter_.layout().total_factors();
  for (std::uint64_t idx = next_release_; idx < seen; ++idx) {
    SmoothedSample s{idx, Eigen::VectorXd(f), Eigen::VectorXd(f)};
    write_lag(static_cast<int>(seen - 1 - idx), s.estimates.data(), s.std_devs.data());
    out.push_back(std::move(s));
  }
  next_release_ = seen;
  return out;
}

}  // namespace causal
