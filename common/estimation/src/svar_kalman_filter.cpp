#include "causal/estimation/svar_kalman_filter.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"
#include "causal/estimation/state_fields.hpp"
#include "causal/io/enum_names.hpp"
#include "kernels.hpp"
#include "lane_plan.hpp"
#include "segment_tracker.hpp"

namespace causal::estimation {

const char* to_string(SampleStatus status) {
  static constexpr auto kNames =
      io::enum_names<SampleStatus>({{SampleStatus::Updated, "updated"},
                                    {SampleStatus::WarmUp, "warm-up"},
                                    {SampleStatus::RejectedNonFinite, "rejected-non-finite"}});
  return kNames.name(status, "unknown");
}

// Binds each lane group to the kernels of its dimension D.
template <int D>
struct SvarKalmanFilter::Select {
  CAUSAL_CORE_CLONES static void update(SvarKalmanFilter& f, int group) {
    using detail::V4;
    const detail::LaneGroup& grp = f.plan_->groups[group];
    const int* yi = f.y_index_.data() + group * detail::kLanes;
    const V4 y{f.window_[yi[0]], f.window_[yi[1]], f.window_[yi[2]], f.window_[yi[3]]};
    V4 e, s;
    detail::joseph_update<D>(grp.d, detail::lanes(f.x_.data() + grp.x_off), detail::lanes(f.p_.data() + grp.p_off),
                             detail::lanes(f.h_.data() + grp.x_off),
                             y, detail::lanes(f.r_.data() + group * detail::kLanes)[0],
                             detail::lanes(f.u_.data() + grp.x_off), e, s, detail::lanes(f.work_.data()));
    detail::lanes(f.e_lane_.data() + group * detail::kLanes)[0] = e;
    detail::lanes(f.s_lane_.data() + group * detail::kLanes)[0] = s;
  }
  static void run(SvarKalmanFilter& f, int group) { f.update_fn_[group] = &update; }
};

SvarKalmanFilter::SvarKalmanFilter(const SvarLayout& layout, std::vector<NoiseParams> noise)
    : SvarKalmanFilter(layout, std::move(noise), nullptr) {}

SvarKalmanFilter::SvarKalmanFilter(const SvarLayout& layout, std::vector<NoiseParams> noise,
                                   std::shared_ptr<const detail::LanePlan> given_plan)
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

  std::shared_ptr<const detail::LanePlan> plan =
      given_plan ? std::move(given_plan) : std::make_shared<const detail::LanePlan>(detail::make_lane_plan(layout_));
  plan_ = plan;
  const int zero_slot = (m_ + 1) * g_;  // window_ index that always holds 0 (padding lanes read it)
  const std::size_t n_groups = plan->groups.size();
  gather_.assign(plan->x_size, zero_slot);
  y_index_.assign(n_groups * detail::kLanes, zero_slot);
  q_.assign(n_groups * detail::kLanes, 0.0);
  r_.assign(n_groups * detail::kLanes, 1.0);
  update_fn_.resize(n_groups);
  for (std::size_t gi = 0; gi < n_groups; ++gi) {
    const detail::LaneGroup& grp = plan->groups[gi];
    for (int w = 0; w < grp.count; ++w) {
      const int k = grp.outcome[w];
      const auto& regs = layout_.regressors(k);
      for (int i = 0; i < grp.d; ++i) {
        gather_[grp.x_off + static_cast<std::size_t>(i) * detail::kLanes + w] = regs[i].lag * g_ + regs[i].channel;
      }
      y_index_[gi * detail::kLanes + w] = k;
    }
    detail::dispatch_dim<Select>(grp.d, *this, static_cast<int>(gi));
  }
  for (int k = 0; k < g_; ++k) set_noise(k, noise_[k]);
  x_.resize(plan->x_size);
  p_.resize(plan->p_size);
  h_.assign(plan->x_size, 0.0);
  u_.assign(plan->x_size, 0.0);
  e_lane_.assign(n_groups * detail::kLanes, 0.0);
  s_lane_.assign(n_groups * detail::kLanes, 1.0);
  e_.resize(g_);
  s_.resize(g_);
  window_.assign(static_cast<std::size_t>(zero_slot) + 1, 0.0);
  work_.resize(detail::kernel_work_lanes(plan->max_d) * detail::kLanes);
  reset();
}

void SvarKalmanFilter::reset() {
  std::fill(x_.begin(), x_.end(), 0.0);
  std::fill(p_.begin(), p_.end(), 0.0);
  for (const detail::LaneGroup& grp : plan_->groups) {
    for (int w = 0; w < detail::kLanes; ++w) {
      const double p0 = w < grp.count ? noise_[grp.outcome[w]].p0 : 1.0;
      for (int i = 0; i < grp.d; ++i) {
        p_[grp.p_off + (static_cast<std::size_t>(i) * grp.d + i) * detail::kLanes + w] = p0;
      }
    }
  }
  std::fill(e_.begin(), e_.end(), std::numeric_limits<double>::quiet_NaN());
  std::fill(s_.begin(), s_.end(), std::numeric_limits<double>::quiet_NaN());
  std::fill(window_.begin(), window_.end(), 0.0);
  history_ = 0;
  steps_ = 0;
  counters_ = FilterCounters{};
}

// The whole step (prediction, screening, lag window, regressor gather, per-outcome scatter) is cloned like the
// update kernels it calls, so the glue between the kernels also runs on 4-wide vectors (and avoids the
// SSE/AVX transition of a baseline caller around AVX clones).
struct SvarKalmanFilter::StepKernel {
  CAUSAL_CORE_CLONES static SampleStatus run(SvarKalmanFilter& f, const double* y, bool discontinuity) {
    const auto& groups = f.plan_->groups;
    const int n_groups = static_cast<int>(groups.size());
    if (f.steps_ > 0) {
      // P += q I for every sample, usable or not: time passes.
      for (int gi = 0; gi < n_groups; ++gi) {
        const detail::LaneGroup& grp = groups[gi];
        detail::V4* p = detail::lanes(f.p_.data() + grp.p_off);
        const detail::V4 q = detail::lanes(f.q_.data() + gi * detail::kLanes)[0];
        for (int i = 0; i < grp.d; ++i) p[i * grp.d + i] += q;
      }
    }
    ++f.steps_;
    const int g = f.g_, m = f.m_;
    const SampleStatus status = detail::classify_sample(y, g, m, discontinuity, f.history_);
    if (status == SampleStatus::RejectedNonFinite) {
      ++f.counters_.rejected_non_finite;
      return status;
    }
    // Shift the lag window by one sample (row l holds y[n-l]) and put y in row 0.
    double* window = f.window_.data();
    std::memmove(window + g, window, sizeof(double) * static_cast<std::size_t>(m * g));
    std::memcpy(window, y, sizeof(double) * static_cast<std::size_t>(g));
    if (status == SampleStatus::WarmUp) {
      ++f.counters_.warm_up;
      return status;
    }
    const std::size_t nh = f.h_.size();
    double* h = f.h_.data();
    const int* gather = f.gather_.data();
    for (std::size_t i = 0; i < nh; ++i) h[i] = window[gather[i]];
    for (int gi = 0; gi < n_groups; ++gi) f.update_fn_[gi](f, gi);
    for (int gi = 0; gi < n_groups; ++gi) {
      const detail::LaneGroup& grp = groups[gi];
      for (int w = 0; w < grp.count; ++w) {
        f.e_[grp.outcome[w]] = f.e_lane_[gi * detail::kLanes + w];
        f.s_[grp.outcome[w]] = f.s_lane_[gi * detail::kLanes + w];
      }
    }
    for (int k : f.plan_->empty) {  // no factors: the whole of y_k is innovation
      f.e_[k] = y[k];
      f.s_[k] = f.noise_[k].r;
    }
    ++f.counters_.updated;
    return status;
  }
};

SampleStatus SvarKalmanFilter::step(const double* y, bool discontinuity) {
  return StepKernel::run(*this, y, discontinuity);
}

double SvarKalmanFilter::last_innovation(int k) const { return e_.at(k); }

double SvarKalmanFilter::last_innovation_variance(int k) const { return s_.at(k); }

Eigen::VectorXd SvarKalmanFilter::estimate(int k) const {
  const int d = layout_.factor_count(k);
  Eigen::VectorXd v(d);
  if (d == 0) return v;
  const detail::LaneGroup& grp = plan_->groups[plan_->group_of[k]];
  const int w = plan_->lane_of[k];
  for (int i = 0; i < d; ++i) v[i] = x_[grp.x_off + static_cast<std::size_t>(i) * detail::kLanes + w];
  return v;
}

Eigen::MatrixXd SvarKalmanFilter::covariance(int k) const {
  const int d = layout_.factor_count(k);
  Eigen::MatrixXd m(d, d);
  if (d == 0) return m;
  const detail::LaneGroup& grp = plan_->groups[plan_->group_of[k]];
  const int w = plan_->lane_of[k];
  for (int j = 0; j < d; ++j) {
    for (int i = 0; i < d; ++i) {
      m(i, j) = p_[grp.p_off + (static_cast<std::size_t>(j) * d + i) * detail::kLanes + w];
    }
  }
  return m;
}

void SvarKalmanFilter::estimates(double* out) const {
  for (const detail::LaneGroup& grp : plan_->groups) {
    for (int w = 0; w < grp.count; ++w) {
      double* o = out + layout_.offset(grp.outcome[w]);
      for (int i = 0; i < grp.d; ++i) o[i] = x_[grp.x_off + static_cast<std::size_t>(i) * detail::kLanes + w];
    }
  }
}

void SvarKalmanFilter::std_devs(double* out) const {
  for (const detail::LaneGroup& grp : plan_->groups) {
    for (int w = 0; w < grp.count; ++w) {
      double* o = out + layout_.offset(grp.outcome[w]);
      for (int i = 0; i < grp.d; ++i) {
        // A variance <= 0 can only come from rounding (ill-scaled outcome): 0, never a NaN from sqrt. Callers
        // that publish flag zero standard deviations (FactorReport::degenerate_std).
        const double v = p_[grp.p_off + (static_cast<std::size_t>(i) * grp.d + i) * detail::kLanes + w];
        o[i] = v > 0.0 || std::isnan(v) ? std::sqrt(v) : 0.0;
      }
    }
  }
}

const NoiseParams& SvarKalmanFilter::noise(int k) const { return noise_.at(k); }

void SvarKalmanFilter::set_noise(int k, const NoiseParams& noise) {
  validate_noise_params(noise, "set_noise(" + std::to_string(k) + ")");
  noise_.at(k) = noise;
  const int gi = plan_->group_of[k];
  if (gi < 0) return;
  q_[gi * detail::kLanes + plan_->lane_of[k]] = noise.q;
  r_[gi * detail::kLanes + plan_->lane_of[k]] = noise.r;
}

template <class IO, class Self>
void SvarKalmanFilter::fields(IO io, Self& f) {
  for (auto& n : f.noise_) {
    io(n.q, n.r, n.p0);
  }
  io.same_size(f.x_, "filter state");
  io.same_size(f.p_, "filter covariance");
  io.same_size(f.e_, "last innovations");
  io.same_size(f.s_, "last innovation variances");
  io.same_size(f.window_, "lag window");
  io.template as<std::int32_t>(f.history_);
  io(f.steps_, f.counters_.updated, f.counters_.warm_up, f.counters_.rejected_non_finite);
}

void SvarKalmanFilter::save(StateWriter& w) const {
  w.begin("svar_kalman_filter", 1);
  save_model_spec(w, layout_.spec());
  fields(SaveFields{w}, *this);
}

void SvarKalmanFilter::restore(StateReader& r) {
  r.expect("svar_kalman_filter", 1);
  expect_same_model(read_model_spec(r), layout_.spec(), "filter");
  // Everything is read into a copy first: a damaged checkpoint leaves this filter as it was.
  SvarKalmanFilter f = *this;
  fields(RestoreFields{r}, f);
  for (std::size_t k = 0; k < f.noise_.size(); ++k) {
    try {
      validate_noise_params(f.noise_[k], "noise[" + std::to_string(k) + "]");
    } catch (const std::invalid_argument& e) {
      throw StateError(std::string("checkpoint holds invalid filter noise: ") + e.what());
    }
    f.set_noise(static_cast<int>(k), f.noise_[k]);
  }
  if (f.history_ < 0 || f.history_ > m_) throw StateError("checkpoint: filter lag history out of range");
  *this = std::move(f);
}

}  // namespace causal::estimation
