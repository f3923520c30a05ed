#include "causal/estimation/batch_estimation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "causal/estimation/fixed_lag_smoother.hpp"
#include "filter_access.hpp"
#include "rts_pass.hpp"

namespace causal::estimation {
namespace {

using detail::FilterAccess;
using detail::kLanes;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::Index kept_rows(Eigen::Index n, Eigen::Index every) { return n == 0 ? 0 : (n - 1) / every + 1; }

EstimationRun prepare(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                      const std::vector<bool>& discontinuity, const BatchOutput& output) {
  if (output.every < 1) {
    throw std::invalid_argument("BatchOutput.every must be >= 1, got " + std::to_string(output.every));
  }
  EstimationRun run;
  run.status = detail::classify_all(layout, samples, discontinuity);  // validates the shapes
  const Eigen::Index n = samples.rows();
  const Eigen::Index rows = kept_rows(n, output.every);
  run.estimates.resize(rows, layout.total_factors());
  run.std_devs.resize(rows, layout.total_factors());
  const Eigen::Index innovation_rows = output.innovations ? n : 0;
  run.innovations = Eigen::MatrixXd::Constant(innovation_rows, layout.channels(), kNaN);
  run.innovation_variances = Eigen::MatrixXd::Constant(innovation_rows, layout.channels(), kNaN);
  for (SampleStatus s : run.status) {
    switch (s) {
      case SampleStatus::Updated: ++run.counters.updated; break;
      case SampleStatus::WarmUp: ++run.counters.warm_up; break;
      case SampleStatus::RejectedNonFinite: ++run.counters.rejected_non_finite; break;
    }
  }
  return run;
}

// Steps the filter with sample i and records its innovations.
void step(SvarKalmanFilter& f, const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
          Eigen::Index i, std::vector<double>& row, EstimationRun* run) {
  const int g = static_cast<int>(samples.cols());
  for (int j = 0; j < g; ++j) row[j] = samples(i, j);
  const SampleStatus st = f.step(row.data(), !discontinuity.empty() && discontinuity[i]);
  if (run == nullptr || st != SampleStatus::Updated || run->innovations.rows() == 0) return;
  for (int k = 0; k < g; ++k) {
    run->innovations(i, k) = FilterAccess::e(f)[k];
    run->innovation_variances(i, k) = FilterAccess::s(f)[k];
  }
}

// Writes the kept samples of a block (slot t = sample lo + t; lane-interleaved x and sd, `stride` doubles per
// slot) into the output rows, column by column (the outputs are column-major). The output row is counted
// along, not computed as n / every per value: an integer division per value was the largest single cost of
// run_filter (one per factor and sample, more than the filter update itself).
void scatter(const SvarLayout& layout, const detail::LanePlan& plan, const double* xbuf, const double* sdbuf,
             std::size_t stride, Eigen::Index lo, Eigen::Index count, Eigen::Index every, EstimationRun& run) {
  const Eigen::Index first = (lo + every - 1) / every * every;
  if (first >= lo + count) return;
  const Eigen::Index first_row = first / every;
  const Eigen::Index kept = (lo + count - 1 - first) / every + 1;
  const std::size_t slot_step = static_cast<std::size_t>(every) * stride;
  const std::size_t first_slot = static_cast<std::size_t>(first - lo) * stride;
  for (const detail::LaneGroup& grp : plan.groups) {
    for (int w = 0; w < grp.count; ++w) {
      const int off = layout.offset(grp.outcome[w]);
      for (int i = 0; i < grp.d; ++i) {
        const std::size_t j = first_slot + grp.x_off + static_cast<std::size_t>(i) * kLanes + w;
        double* xc = run.estimates.col(off + i).data() + first_row;
        double* sc = run.std_devs.col(off + i).data() + first_row;
        for (Eigen::Index r = 0; r < kept; ++r) {
          const std::size_t at = j + static_cast<std::size_t>(r) * slot_step;
          xc[r] = xbuf[at];
          sc[r] = sdbuf[at];
        }
      }
    }
  }
}

// Copies the filter's lane-interleaved x and sqrt(diag P) into one buffer slot; returns how many real lanes
// had a variance <= 0 (reported as standard deviation 0).
std::uint64_t snapshot(const SvarKalmanFilter& f, const detail::LanePlan& plan, double* xslot, double* sdslot) {
  const std::vector<double>& x = FilterAccess::x(f);
  const std::vector<double>& p = FilterAccess::p(f);
  std::copy(x.begin(), x.end(), xslot);
  std::uint64_t clamped = 0;
  for (const detail::LaneGroup& grp : plan.groups) {
    for (int i = 0; i < grp.d; ++i) {
      const double* v = p.data() + grp.p_off + (static_cast<std::size_t>(i) * grp.d + i) * kLanes;
      double* sd = sdslot + grp.x_off + static_cast<std::size_t>(i) * kLanes;
      for (int w = 0; w < kLanes; ++w) {
        // Rounding can leave a variance <= 0 after many updates of an ill-scaled outcome: report 0 and count
        // it (the caller decides what to say); a NaN stays NaN, visible to the caller's output check.
        const bool usable = v[w] > 0.0 || std::isnan(v[w]);
        sd[w] = usable ? std::sqrt(v[w]) : 0.0;
        clamped += static_cast<std::uint64_t>(!usable && w < grp.count);
      }
    }
  }
  return clamped;
}

EstimationRun filter_pass(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                          const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                          const BatchOutput& output) {
  EstimationRun run = prepare(layout, samples, discontinuity, output);
  SvarKalmanFilter f(layout, noise);
  const detail::LanePlan& plan = FilterAccess::plan(f);
  const std::size_t nx = plan.x_size;
  const Eigen::Index n = samples.rows();
  // Outputs are column-major: writing one sample at a time would touch 2 F cache lines per sample, so a few
  // samples are buffered (small enough to stay in L1) and then written column by column.
  constexpr Eigen::Index kOutBlock = 64;
  const Eigen::Index block = std::min<Eigen::Index>(kOutBlock, std::max<Eigen::Index>(n, 1));
  std::vector<double> row(samples.cols()), xbuf(static_cast<std::size_t>(block) * nx), sdbuf(xbuf.size());
  for (Eigen::Index lo = 0; lo < n; lo += block) {
    const Eigen::Index count = std::min(block, n - lo);
    Eigen::Index until_kept = (output.every - lo % output.every) % output.every;  // samples to the next kept one
    for (Eigen::Index t = 0; t < count; ++t) {
      step(f, samples, discontinuity, lo + t, row, &run);
      if (until_kept-- != 0) continue;
      until_kept = output.every - 1;
      run.clamped_variances += snapshot(f, plan, xbuf.data() + t * nx, sdbuf.data() + t * nx);
    }
    scatter(layout, plan, xbuf.data(), sdbuf.data(), nx, lo, count, output.every, run);
  }
  return run;
}

EstimationRun rts_pass(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                       const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                       const BatchOutput& output) {
  EstimationRun run = prepare(layout, samples, discontinuity, output);
  const Eigen::Index n = samples.rows();
  SvarKalmanFilter f(layout, noise);
  std::vector<double> row(samples.cols());
  // Forward: innovations, and a copy of the filter at the start of every block.
  std::vector<SvarKalmanFilter> checkpoints;
  checkpoints.reserve(static_cast<std::size_t>((n + kRtsBlock - 1) / kRtsBlock));
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i % kRtsBlock == 0) checkpoints.push_back(f);
    step(f, samples, discontinuity, i, row, &run);
  }
  if (n == 0) return run;
  const detail::LanePlan& plan = FilterAccess::plan(f);
  const std::size_t np = plan.p_size, nx = plan.x_size;
  const Eigen::Index block = std::min(kRtsBlock, n);
  std::vector<double> store(static_cast<std::size_t>(block) * (np + nx));
  std::vector<double> xbuf(static_cast<std::size_t>(block) * nx), sdbuf(xbuf.size());
  std::vector<detail::RtsCarry> carry(plan.groups.size());
  std::vector<std::array<double, kLanes>> q(plan.groups.size());
  for (std::size_t gi = 0; gi < plan.groups.size(); ++gi) {
    for (int w = 0; w < kLanes; ++w) q[gi][w] = FilterAccess::lane_q(f, static_cast<int>(gi), w);
  }
  // Backward, last block first: recompute the block's filtered states from its checkpoint (the same steps, so
  // the same values), then smooth it, carrying the smoothed state to the block before.
  for (auto b = static_cast<Eigen::Index>(checkpoints.size()) - 1; b >= 0; --b) {
    const Eigen::Index lo = b * kRtsBlock;
    const Eigen::Index count = std::min(kRtsBlock, n - lo);
    SvarKalmanFilter g = std::move(checkpoints[b]);
    checkpoints.pop_back();
    for (Eigen::Index t = 0; t < count; ++t) {
      step(g, samples, discontinuity, lo + t, row, nullptr);
      double* slot = store.data() + static_cast<std::size_t>(t) * (np + nx);
      std::copy(FilterAccess::p(g).begin(), FilterAccess::p(g).end(), slot);
      std::copy(FilterAccess::x(g).begin(), FilterAccess::x(g).end(), slot + np);
    }
    const detail::FilteredBlock filtered{store.data(), np + nx, np, count};
    detail::SmoothedBlock smoothed{xbuf.data(), sdbuf.data(), nx, 0};
    for (std::size_t gi = 0; gi < plan.groups.size(); ++gi) {
      detail::run_group_rts_block(plan.groups[gi], q[gi], filtered, carry[gi], smoothed);
    }
    run.clamped_variances += static_cast<std::uint64_t>(smoothed.clamped_variances);
    scatter(layout, plan, xbuf.data(), sdbuf.data(), nx, lo, count, output.every, run);
  }
  return run;
}

}  // namespace

EstimationRun run_filter(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                         const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                         const BatchOutput& output) {
  return filter_pass(layout, noise, samples, discontinuity, output);
}

EstimationRun run_rts_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                               const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                               const BatchOutput& output) {
  return rts_pass(layout, noise, samples, discontinuity, output);
}

EstimationRun run_fixed_lag_smoother(const SvarLayout& layout, const std::vector<NoiseParams>& noise,
                                     const Eigen::MatrixXd& samples, const std::vector<bool>& discontinuity,
                                     int lag, const BatchOutput& output) {
  EstimationRun run = prepare(layout, samples, discontinuity, output);  // validates shapes
  FixedLagSmoother smoother(layout, noise, lag);
  const Eigen::Index n = samples.rows();
  const int g = layout.channels();
  std::vector<double> row(g);
  auto store = [&](const SmoothedSample& s) {
    const auto i = static_cast<Eigen::Index>(s.index);
    if (i % output.every != 0) return;
    run.estimates.row(i / output.every) = s.estimates.transpose();
    run.std_devs.row(i / output.every) = s.std_devs.transpose();
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int j = 0; j < g; ++j) row[j] = samples(i, j);
    const bool disc = !discontinuity.empty() && discontinuity[i];
    if (auto out = smoother.step(row.data(), disc)) store(*out);
    if (run.status[i] == SampleStatus::Updated && output.innovations) {
      for (int k = 0; k < g; ++k) {
        run.innovations(i, k) = smoother.filter().last_innovation(k);
        run.innovation_variances(i, k) = smoother.filter().last_innovation_variance(k);
      }
    }
  }
  for (const SmoothedSample& s : smoother.flush()) store(s);
  return run;
}

}  // namespace causal::estimation
