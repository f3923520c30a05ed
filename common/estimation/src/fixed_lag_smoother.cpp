#include "causal/estimation/fixed_lag_smoother.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"
#include "causal/estimation/state_fields.hpp"
#include "kernels.hpp"
#include "lane_plan.hpp"

namespace causal::estimation {

// Lag update of one lane group with the filter's last regressors h, u = P[n|n-1] h, innovation e and
// variance S (equations in the header), for every lagged slot i = 1..active.
template <int D>
struct FixedLagSmoother::Select {
  CAUSAL_CORE_CLONES static void update(FixedLagSmoother& s, int group) {
    using detail::V4;
    const SvarKalmanFilter& f = s.filter_;
    const detail::LaneGroup& grp = f.plan_->groups[group];
    const int d = grp.d;
    const V4* h = detail::lanes(f.h_.data() + grp.x_off);
    const V4* u = detail::lanes(f.u_.data() + grp.x_off);
    const V4 e = detail::lanes(f.e_lane_.data() + group * detail::kLanes)[0];
    const V4 sv = detail::lanes(f.s_lane_.data() + group * detail::kLanes)[0];
    const V4 inv_s = 1.0 / sv;
    const std::size_t l = static_cast<std::size_t>(s.lag_);
    V4* xs = detail::lanes(s.xs_.data() + l * grp.x_off);
    V4* pc = detail::lanes(s.pc_.data() + l * grp.p_off);
    V4* var = detail::lanes(s.var_.data() + l * grp.x_off);
    V4* work = detail::lanes(s.work_.data());
    // Only the slots of released samples (n - slot + 1) % m == 0, i.e. slot = first, first + m, ...: the
    // others are never read (decimation; m = 1 updates every slot).
    const std::uint64_t m = s.release_every_;
    const std::uint64_t r = f.samples_seen() % m;  // samples_seen() = n + 1
    const std::uint64_t first = r == 0 ? m : r;     // smallest slot >= 1 with slot = n + 1 (mod m)
    for (std::uint64_t slot_u = first; slot_u <= static_cast<std::uint64_t>(s.active_); slot_u += m) {
      const int slot = static_cast<int>(slot_u);
      const auto pos = static_cast<std::size_t>(s.slot_pos(slot));
      detail::lag_update<D>(d, h, u, e, sv, inv_s, pc + pos * d * d, xs + pos * d, var + pos * d, work);
    }
  }
  static void run(FixedLagSmoother& s, int group) { s.update_fn_[group] = &update; }
};

FixedLagSmoother::FixedLagSmoother(const SvarLayout& layout, std::vector<NoiseParams> noise, int lag,
                                   std::uint64_t release_every)
    : filter_(layout, std::move(noise)), lag_(lag), release_every_(release_every) {
  if (lag < 0) throw std::invalid_argument("FixedLagSmoother: lag must be >= 0, got " + std::to_string(lag));
  if (release_every < 1) throw std::invalid_argument("FixedLagSmoother: release_every must be >= 1");
  const detail::LanePlan& plan = *filter_.plan_;
  update_fn_.resize(plan.groups.size());
  for (std::size_t gi = 0; gi < plan.groups.size(); ++gi) {
    detail::dispatch_dim<Select>(plan.groups[gi].d, *this, static_cast<int>(gi));
  }
  const auto l = static_cast<std::size_t>(lag_);
  xs_.assign(l * plan.x_size, 0.0);
  var_.assign(l * plan.x_size, 0.0);
  pc_.assign(l * plan.p_size, 0.0);
  work_.assign(detail::kernel_work_lanes(plan.max_d) * detail::kLanes, 0.0);
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
  if (!released(filter_.samples_seen() - 1)) return;  // the slot of a sample that is never released stays unused
  const auto l = static_cast<std::size_t>(lag_);
  const auto pos = static_cast<std::size_t>(head_);
  for (const detail::LaneGroup& grp : filter_.plan_->groups) {
    const std::size_t nx = static_cast<std::size_t>(grp.d) * detail::kLanes;
    const std::size_t np = nx * grp.d;
    const double* fx = filter_.x_.data() + grp.x_off;
    const double* fp = filter_.p_.data() + grp.p_off;
    std::copy(fx, fx + nx, xs_.data() + l * grp.x_off + pos * nx);
    std::copy(fp, fp + np, pc_.data() + l * grp.p_off + pos * np);
    double* v = var_.data() + l * grp.x_off + pos * nx;
    for (int i = 0; i < grp.d; ++i) {
      for (int w = 0; w < detail::kLanes; ++w) {
        v[i * detail::kLanes + w] = fp[(static_cast<std::size_t>(i) * grp.d + i) * detail::kLanes + w];
      }
    }
  }
}

void FixedLagSmoother::write_lag(int i, double* estimates, double* std_devs) const {
  if (i == 0) {
    filter_.estimates(estimates);
    filter_.std_devs(std_devs);
    return;
  }
  const auto l = static_cast<std::size_t>(lag_);
  const auto pos = static_cast<std::size_t>(slot_pos(i));
  const SvarLayout& layout = filter_.layout();
  for (const detail::LaneGroup& grp : filter_.plan_->groups) {
    const std::size_t nx = static_cast<std::size_t>(grp.d) * detail::kLanes;
    const double* x = xs_.data() + l * grp.x_off + pos * nx;
    const double* v = var_.data() + l * grp.x_off + pos * nx;
    for (int w = 0; w < grp.count; ++w) {
      const int off = layout.offset(grp.outcome[w]);
      for (int j = 0; j < grp.d; ++j) {
        estimates[off + j] = x[j * detail::kLanes + w];
        std_devs[off + j] = std::sqrt(std::max(v[j * detail::kLanes + w], 0.0));
      }
    }
  }
}

bool FixedLagSmoother::step_into(const double* y, bool discontinuity, std::uint64_t* index, double* estimates,
                                 double* std_devs) {
  if (filter_.samples_seen() > 0) shift_in_filter_state();
  last_status_ = filter_.step(y, discontinuity);
  if (last_status_ == SampleStatus::Updated) {
    for (std::size_t gi = 0; gi < update_fn_.size(); ++gi) update_fn_[gi](*this, static_cast<int>(gi));
  }
  const std::uint64_t n = filter_.samples_seen() - 1;
  if (n < static_cast<std::uint64_t>(lag_)) return false;
  const std::uint64_t release = n - static_cast<std::uint64_t>(lag_);
  if (release < next_release_) return false;  // already flushed
  next_release_ = release + 1;
  if (!released(release)) return false;
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
    if (!released(idx)) continue;
    SmoothedSample s{idx, Eigen::VectorXd(f), Eigen::VectorXd(f)};
    write_lag(static_cast<int>(seen - 1 - idx), s.estimates.data(), s.std_devs.data());
    out.push_back(std::move(s));
  }
  next_release_ = seen;
  return out;
}

template <class IO, class Self>
void FixedLagSmoother::fields(IO io, Self& s) {
  io.tag("fixed_lag_smoother", 1);
  io.template same_as<std::int32_t>(s.lag_, "fixed lag", "smoother");
  io.same(s.release_every_, "release_every", "smoother");
  io.object(s.filter_);
  io.same_size(s.xs_, "smoother lagged states");
  io.same_size(s.pc_, "smoother cross-covariances");
  io.same_size(s.var_, "smoother variances");
  io.template as<std::int32_t>(s.head_);
  io.template as<std::int32_t>(s.active_);
  io(s.next_release_, s.last_status_);
}

void FixedLagSmoother::save(StateWriter& w) const { fields(SaveFields{w}, *this); }

void FixedLagSmoother::restore(StateReader& r) {
  // Into a copy first: a damaged checkpoint leaves this smoother as it was.
  FixedLagSmoother s = *this;
  fields(RestoreFields{r}, s);
  const int head = s.head_, active = s.active_;
  const SampleStatus status = s.last_status_;
  const bool head_ok = lag_ == 0 ? head == 0 : head >= 0 && head < lag_;
  if (!head_ok || active < 0 || active > lag_ || s.next_release_ > s.filter_.samples_seen() ||
      (status != SampleStatus::Updated && status != SampleStatus::WarmUp &&
       status != SampleStatus::RejectedNonFinite)) {
    throw StateError("checkpoint: fixed-lag smoother ring state out of range");
  }
  *this = std::move(s);
}

}  // namespace causal::estimation
