#include "rts_pass.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kernels.hpp"
#include "segment_tracker.hpp"

namespace causal::estimation::detail {

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

namespace {

// Backward pass: rts_gain / rts_apply (kernels.hpp) from the block's last slot down.
template <int D>
struct RtsOp {
  CAUSAL_CORE_CLONES static void run(const LaneGroup& grp, const std::array<double, kLanes>& q_lanes,
                                     const FilteredBlock& block, RtsCarry& carry, SmoothedBlock& out) {
    const int d = grp.d;
    if (block.count == 0) return;
    const std::size_t np = static_cast<std::size_t>(d) * d * kLanes;
    const std::size_t nx = static_cast<std::size_t>(d) * kLanes;
    const V4 q{q_lanes[0], q_lanes[1], q_lanes[2], q_lanes[3]};
    std::vector<double> work(kernel_work_lanes(d) * kLanes);
    carry.ps.resize(np);
    carry.xs.resize(nx);
    auto pf_of = [&](Eigen::Index t) { return block.data + static_cast<std::size_t>(t) * block.stride + grp.p_off; };
    auto xf_of = [&](Eigen::Index t) {
      return block.data + static_cast<std::size_t>(t) * block.stride + block.p_size + grp.x_off;
    };
    auto emit = [&](Eigen::Index t) {
      double* xo = out.x + static_cast<std::size_t>(t) * out.stride + grp.x_off;
      std::copy(carry.xs.begin(), carry.xs.end(), xo);
      V4* sd = lanes(out.sd + static_cast<std::size_t>(t) * out.stride + grp.x_off);
      const V4* p = lanes(carry.ps.data());
      for (int i = 0; i < d; ++i) {
        const V4 v = p[i * d + i];
        for (int w = 0; w < kLanes; ++w) {
          if (v[w] > 0.0 || std::isnan(v[w])) {  // NaN stays visible (the caller reports it), never hidden
            sd[i][w] = std::sqrt(v[w]);
          } else {
            sd[i][w] = 0.0;
            if (w < grp.count) ++out.clamped_variances;
          }
        }
      }
    };
    Eigen::Index top = block.count - 1;
    if (!carry.started) {  // the record's last sample: smoothed = filtered
      std::copy(pf_of(top), pf_of(top) + np, carry.ps.begin());
      std::copy(xf_of(top), xf_of(top) + nx, carry.xs.begin());
      carry.started = true;
      emit(top);
      --top;
    }
    // Gains first for a chunk of samples (independent of the smoothed values), then the sequential part.
    constexpr Eigen::Index kChunk = 8;
    std::vector<double> gains(static_cast<std::size_t>(kChunk) * np);
    std::array<bool, kChunk> ok{};
    for (Eigen::Index hi = top; hi >= 0; hi -= kChunk) {
      const Eigen::Index lo = std::max<Eigen::Index>(0, hi - kChunk + 1);
      for (Eigen::Index t = hi; t >= lo; --t) {
        ok[hi - t] = rts_gain<D>(d, q, lanes(pf_of(t)), lanes(gains.data() + (hi - t) * np), lanes(work.data()));
      }
      for (Eigen::Index t = hi; t >= lo; --t) {
        if (ok[hi - t]) {
          rts_apply<D>(d, q, lanes(pf_of(t)), lanes(xf_of(t)), lanes(gains.data() + (hi - t) * np),
                       lanes(carry.ps.data()), lanes(carry.xs.data()), lanes(work.data()));
        } else {
          // P[n+1|n] = P[n|n] + q I not SPD (cannot happen for p0 > 0, r > 0 short of overflow): fall back to
          // the filtered values rather than emit garbage.
          std::copy(pf_of(t), pf_of(t) + np, carry.ps.begin());
          std::copy(xf_of(t), xf_of(t) + nx, carry.xs.begin());
        }
        emit(t);
      }
    }
  }
};

}  // namespace

void run_group_rts_block(const LaneGroup& grp, const std::array<double, kLanes>& q, const FilteredBlock& block,
                         RtsCarry& carry, SmoothedBlock& out) {
  dispatch_dim<RtsOp>(grp.d, grp, q, block, carry, out);
}

}  // namespace causal::estimation::detail
