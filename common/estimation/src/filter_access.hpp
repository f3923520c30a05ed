// Internal view of SvarKalmanFilter for the passes built on top of it (batch filter / RTS, noise tuning):
// they step the ONE filter recursion and read its lane-interleaved state directly instead of re-implementing
// the recursion over whole columns.
#pragma once

#include <memory>
#include <vector>

#include "causal/estimation/svar_kalman_filter.hpp"
#include "kernels.hpp"
#include "lane_plan.hpp"

namespace causal::estimation::detail {

struct FilterAccess {
  static const LanePlan& plan(const SvarKalmanFilter& f) { return *f.plan_; }
  // Lane-interleaved states / covariances of all groups (LaneGroup::x_off / p_off index into them).
  static const std::vector<double>& x(const SvarKalmanFilter& f) { return f.x_; }
  static const std::vector<double>& p(const SvarKalmanFilter& f) { return f.p_; }
  // Innovations and their variances per outcome at the last Updated step.
  static const std::vector<double>& e(const SvarKalmanFilter& f) { return f.e_; }
  static const std::vector<double>& s(const SvarKalmanFilter& f) { return f.s_; }
  // Innovation and its variance of lane w of group gi at the last Updated step.
  static double lane_e(const SvarKalmanFilter& f, int gi, int w) { return f.e_lane_[gi * kLanes + w]; }
  static double lane_s(const SvarKalmanFilter& f, int gi, int w) { return f.s_lane_[gi * kLanes + w]; }
  static double lane_q(const SvarKalmanFilter& f, int gi, int w) { return f.q_[gi * kLanes + w]; }

  // A filter whose single group holds outcome k in all 4 lanes, lane w with noise[w] (q, r and the prior
  // p0 I): up to 4 noise candidates of one outcome evaluated by one pass of the same recursion.
  static SvarKalmanFilter replicated(const SvarLayout& layout, int k, const std::vector<NoiseParams>& noise) {
    SvarKalmanFilter f(layout, {noise.front()}, std::make_shared<const LanePlan>(make_replicated_plan(layout, k)));
    const LaneGroup& grp = f.plan_->groups.front();
    for (int w = 0; w < kLanes; ++w) {
      validate_noise_params(noise[w], "candidate noise");
      f.q_[w] = noise[w].q;
      f.r_[w] = noise[w].r;
      for (int i = 0; i < grp.d; ++i) f.p_[grp.p_off + (static_cast<std::size_t>(i) * grp.d + i) * kLanes + w] = noise[w].p0;
    }
    return f;
  }
};

}  // namespace causal::estimation::detail
