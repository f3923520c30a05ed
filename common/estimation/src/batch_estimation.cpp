#include "causal/batch_estimation.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <stdexcept>

#include "causal/fixed_lag_smoother.hpp"
#include "outcome_pass.hpp"

namespace causal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

EstimationRun prepare(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                      const std::vector<bool>& discontinuity) {
  EstimationRun run;
  run.status = detail::classify_all(layout, samples, discontinuity);
  const Eigen::Index n = samples.rows();
  run.estimates.resize(n, layout.total_factors());
  run.std_devs.resize(n, layout.total_factors());
  run.innovations = Eigen::MatrixXd::Constant(n, layout.channels(), kNaN);
  run.innovation_variances = Eigen::MatrixXd::Constant(n, layout.channels(), kNaN);
  for (SampleStatus s : run.status) {
    switch (s) {
      case SampleStatus::Updated: ++run.counters.updated; break;
      case SampleStatus::WarmUp: ++run.counters.warm_up; break;
      case SampleStatus::RejectedNonFinite: ++run.counters.rejected_non_finite; break;
    }
  }
  return run;
}

EstimationRun forward_backward(const SvarLayout& layout, const std::vector<NoiseParams>& noise_in,
                               const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                               bool smooth) {
  const std::vector<NoiseParams> noise = detail::expand_noise(noise_in, layout.channels());
  EstimationRun run = prepare(layout, samples, discontinuity);
  const Eigen::Index n = samples.rows();
  const detail::LanePlan plan = detail::make_lane_plan(layout);
  // RTS history of one group at a time; not zero-initialised (every element is written before it is read).
  std::unique_ptr<double[]> store;
  if (smooth) store.reset(new double[static_cast<std::size_t>(n) * detail::store_doubles_per_sample(plan.max_d)]);
  auto column = [&](Eigen::MatrixXd& m, int k) { return m.data() + static_cast<Eigen::Index>(layout.offset(k)) * n; };
  for (const detail::LaneGroup& grp : plan.groups) {
    detail::GroupForward job;
    job.layout = &layout;
    job.group = &grp;
    job.samples = &samples;
    job.status = &run.status;
    std::array<double, detail::kLanes> q{};
    for (int w = 0; w < grp.count; ++w) {
      const int k = grp.outcome[w];
      job.noise[w] = noise[k];
      q[w] = noise[k].q;
      job.x_cols[w] = smooth ? nullptr : column(run.estimates, k);  // RTS writes the estimates itself
      job.sd_cols[w] = smooth ? nullptr : column(run.std_devs, k);
      job.e_col[w] = run.innovations.col(k).data();
      job.s_col[w] = run.innovation_variances.col(k).data();
    }
    job.store = smooth ? store.get() : nullptr;
    detail::run_group_forward(job);
    run.clamped_variances += static_cast<std::uint64_t>(job.clamped_variances);
    if (smooth) {
      std::array<double*, detail::kLanes> x{}, sd{};
      for (int w = 0; w < grp.count; ++w) {
        x[w] = column(run.estimates, grp.outcome[w]);
        sd[w] = column(run.std_devs, grp.outcome[w]);
      }
      detail::run_group_rts(grp, n, q, store.get(), x, sd);
    }
  }
  for (int k : plan.empty) {  // no factors: the whole of y_k is innovation
    for (Eigen::Index i = 0; i < n; ++i) {
      if (run.status[i] != SampleStatus::Updated) continue;
      run.innovations(i, k) = samples(i, k);
      run.innovation_variances(i, k) = noise[k].r;
    }
  }
  return run;
}

}  // namespace

EstimationRun run_filter(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                         const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity) {
  return forward_backward(layout, noise, samples, discontinuity, false);
}

EstimationRun run_rts_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                               const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity) {
  return forward_backward(layout, noise, samples, discontinuity, true);
}

EstimationRun run_fixed_lag_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                                     const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                                     int lag) {
  EstimationRun run = prepare(layout, samples, discontinuity);  // validates shapes
  FixedLagSmoother smoother(layout, noise, lag);
  const Eigen::Index n = samples.rows();
  const int g = layout.channels();
  std::vector<double> row(g);
  auto store = [&](const SmoothedSample& s) {
    const auto i = static_cast<Eigen::Index>(s.index);
    run.estimates.row(i) = s.estimates.transpose();
    run.std_devs.row(i) = s.std_devs.transpose();
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int j = 0; j < g; ++j) row[j] = samples(i, j);
    const bool disc = !discontinuity.empty() && discontinuity[i];
    if (auto out = smoother.step(row.data(), disc)) store(*out);
    if (run.status[i] == SampleStatus::Updated) {
      for (int k = 0; k < g; ++k) {
        run.innovations(i, k) = smoother.filter().last_innovation(k);
        run.innovation_variances(i, k) = smoother.filter().last_innovation_variance(k);
      }
    }
  }
  for (const SmoothedSample& s : smoother.flush()) store(s);
  return run;
}

}  // namespace causal
