// Rauch-Tung-Striebel backward pass of one lane group (up to 4 outcomes of equal dimension, lane_plan.hpp)
// over a BLOCK of filtered states. The batch smoother (batch_estimation.cpp) recomputes the filtered states
// block by block from filter checkpoints, last block first, and carries the smoothed state of each group from
// one block to the one before: resident memory is one block, not the whole record.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "causal/estimation/svar_kalman_filter.hpp"
#include "causal/estimation/svar_layout.hpp"
#include "lane_plan.hpp"

namespace causal::estimation::detail {

// Status of every sample, exactly as SvarKalmanFilter::step reports it (same classify_sample). Throws
// std::invalid_argument if samples.cols() != G or discontinuity is neither empty nor of size N.
std::vector<SampleStatus> classify_all(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                       const std::vector<bool>& discontinuity);

// Filtered states of `count` consecutive samples: slot t holds the filter's whole lane-interleaved
// covariance (p_size doubles) then state (x_size doubles) after sample lo + t, `stride` doubles per slot.
struct FilteredBlock {
  const double* data = nullptr;
  std::size_t stride = 0;
  std::size_t p_size = 0;
  Eigen::Index count = 0;
};

// Smoothed covariance and state of one group at the sample after the current block (lane-interleaved).
struct RtsCarry {
  std::vector<double> ps, xs;
  bool started = false;  // false: the block holds the record's last sample, where smoothed = filtered
};

// Outputs per slot, in the filter's lane-interleaved layout (x_size doubles per slot, group at x_off):
// smoothed x[n|N-1] and sqrt(diag P[n|N-1]) (a variance <= 0 from rounding is reported as 0 and counted).
struct SmoothedBlock {
  double* x = nullptr;
  double* sd = nullptr;
  std::size_t stride = 0;
  std::int64_t clamped_variances = 0;
};

// Backward pass of group `grp` (process noise q per lane) from slot count-1 down to 0.
void run_group_rts_block(const LaneGroup& grp, const std::array<double, kLanes>& q, const FilteredBlock& block,
                         RtsCarry& carry, SmoothedBlock& out);

}  // namespace causal::estimation::detail
