#include "causal/batch_estimation.hpp"

#include <algorithm>
#include <limits>
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
  std::vector<double> p_store;
  if (smooth) p_store.resize(static_cast<std::size_t>(n) * layout.max_factor_count() * layout.max_factor_count());
  for (int k = 0; k < layout.channels(); ++k) {
    const int d = layout.factor_count(k);
    detail::OutcomeForward job;
    job.layout = &layout;
    job.k = k;
    job.samples = &samples;
    job.status = &run.status;
    job.noise = noise[k];
    job.x_cols = run.estimates.data() + static_cast<Eigen::Index>(layout.offset(k)) * n;
    job.sd_cols = smooth ? nullptr : run.std_devs.data() + static_cast<Eigen::Index>(layout.offset(k)) * n;
    job.e_col = run.innovations.col(k).data();
    job.s_col = run.innovation_variances.col(k).data();
    job.p_store = smooth ? p_store.data() : nullptr;
    detail::run_outcome_forward(job);
    if (smooth) {
      detail::run_outcome_rts(d, n, noise[k].q, p_store.data(), job.x_cols,
                              run.std_devs.data() + static_cast<Eigen::Index>(layout.offset(k)) * n);
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
