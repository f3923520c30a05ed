#include "block_order.hpp"

#include "causal/analysis/causal_graph.hpp"
#include "causal/analysis/order_trust.hpp"

#include <algorithm>
#include <stdexcept>

namespace causal::pipeline {

std::size_t samples_per_block_channel(int lag_order) {
  return 10 * static_cast<std::size_t>(lag_order + 1);
}

std::vector<std::vector<int>> order_blocks(int g, int lag_order, std::size_t window) {
  const std::size_t per_channel = samples_per_block_channel(lag_order);
  const int widest = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(g), window / per_channel));
  const int count = widest >= 2 ? (g + widest - 1) / widest : 1;
  std::vector<std::vector<int>> blocks(static_cast<std::size_t>(count));
  int next = 0;
  for (int b = 0; b < count; ++b) {
    const int size = g / count + (b < g % count ? 1 : 0);  // sizes differ by at most one
    for (int i = 0; i < size; ++i) blocks[static_cast<std::size_t>(b)].push_back(next++);
  }
  return blocks;
}

namespace {

Eigen::MatrixXd columns(const Eigen::MatrixXd& samples, const std::vector<int>& block) {
  Eigen::MatrixXd out(samples.rows(), static_cast<Eigen::Index>(block.size()));
  for (std::size_t i = 0; i < block.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = samples.col(block[i]);
  return out;
}

}  // namespace

BlockOrder learn_block_order(const Eigen::MatrixXd& samples, const std::vector<std::vector<int>>& blocks,
                             const analysis::VarLingamOptions& options) {
  const auto g = static_cast<std::size_t>(samples.cols());
  BlockOrder out;
  out.b0 = Eigen::MatrixXd::Zero(samples.cols(), samples.cols());
  out.allowed.assign(g, std::vector<bool>(g, false));
  for (std::size_t bi = 0; bi < blocks.size(); ++bi) {
    const std::vector<int>& block = blocks[bi];
    if (block.size() < 2) {  // one channel: nothing instantaneous to order
      out.order.push_back(block.front());
      continue;
    }
    const analysis::VarLingamResult result = analysis::var_lingam(columns(samples, block), options);
    if (!result.b0.allFinite()) {  // data so ill-scaled that the fit lost all precision: not an order
      throw std::invalid_argument("VAR-LiNGAM gave non-finite coefficients (ill-scaled calibration window)");
    }
    for (const int local : result.order) out.order.push_back(block[static_cast<std::size_t>(local)]);
    for (std::size_t k = 0; k < block.size(); ++k) {
      for (std::size_t j = 0; j < block.size(); ++j) {
        out.b0(block[k], block[j]) = result.b0(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j));
        out.allowed[static_cast<std::size_t>(block[k])][static_cast<std::size_t>(block[j])] = result.instantaneous_allowed[k][j];
      }
    }
    const analysis::OrderTrust trust = analysis::assess_order(result);
    out.confidence = std::min(out.confidence, trust.confidence);
    out.trusted = out.trusted && trust.trusted;
    if (blocks.size() == 1) {
      out.summary = trust.summary;
    } else {
      out.summary += (out.summary.empty() ? "" : "; ") + std::string("channels ") + std::to_string(block.front() + 1) +
                     "-" + std::to_string(block.back() + 1) + ": " + trust.summary;
    }
  }
  return out;
}

estimation::ModelSpec restrict_to_blocks(estimation::ModelSpec spec, const BlockOrder& learned) {
  spec = analysis::restrict_to_order(std::move(spec), learned.order);  // intersects an existing mask
  const std::size_t g = learned.allowed.size();
  for (std::size_t k = 0; k < g; ++k)
    for (std::size_t j = 0; j < g; ++j) spec.instantaneous_allowed[k][j] = spec.instantaneous_allowed[k][j] && learned.allowed[k][j];
  return spec;
}

}  // namespace causal::pipeline
