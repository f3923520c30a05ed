// The instantaneous causal order of a condition-level group, learned per block of channels when the
// calibration window is too short for one dense VAR-LiNGAM over all of them.
//
// Why blocks: VAR-LiNGAM identifies a G-channel order from a window of at least 10 x G x (M + 1) samples
// (10 samples per VAR(M) regressor of each equation, plus the G x G instantaneous matrix). Raising the
// window with G (400 snapshots for 20 channels at lag 1, 67 hours at IMS cadence) makes the twin learn
// "healthy" on up to four times more of the run, possibly on the wear itself. The window is kept as
// configured instead and the order is identified where the data can identify it: in contiguous blocks of at
// most b = window / (10 x (M + 1)) channels (5 at the shipped 100 snapshots, lag 1), in the table's column
// order, sizes as equal as possible. Within a block VAR-LiNGAM runs as before; there are no instantaneous
// links between blocks (a block-diagonal B0). The lagged regressors of the filter stay dense (every channel's
// past in every equation): the Kalman filter tracks them as random walks from a prior and needs no window.
// Column order is the sensor layout (channels of one bearing, one machine part next to each other), so a
// block is a group of neighbouring sensors. One block (the window suffices) is exactly the dense learning.
#pragma once

#include "causal/analysis/var_lingam.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace causal::pipeline {

// 10 x (M + 1) samples per channel of a block.
std::size_t samples_per_block_channel(int lag_order);
// Contiguous blocks of 0..g-1 whose dense order a window of `window` samples identifies; one block when the
// window holds 10 x g x (M + 1). Every block has >= 2 channels unless the window is below 10 x 2 x (M + 1)
// (then one block: the dense learning, which fails with its own message).
std::vector<std::vector<int>> order_blocks(int g, int lag_order, std::size_t window);

struct BlockOrder {
  std::vector<int> order;                              // causes first within each block, blocks in order
  Eigen::MatrixXd b0;                                  // G x G, zero between blocks
  std::vector<std::vector<bool>> allowed;              // [k][j]: j precedes k in the same block
  double confidence = 1.0;                             // the smallest block confidence (order_trust.hpp)
  bool trusted = true;                                 // every block trusted
  std::string summary;                                 // one line (per block when more than one)
};

// samples: N x G (centred, NaN rows at discontinuities). Throws std::invalid_argument as var_lingam does
// (for the first block that fails) or when the coefficients are not finite.
BlockOrder learn_block_order(const Eigen::MatrixXd& samples, const std::vector<std::vector<int>>& blocks,
                             const analysis::VarLingamOptions& options);

// spec restricted to the learned order: j -> k only where allowed[k][j] (intersected with spec's own mask).
estimation::ModelSpec restrict_to_blocks(estimation::ModelSpec spec, const BlockOrder& learned);

}  // namespace causal::pipeline
