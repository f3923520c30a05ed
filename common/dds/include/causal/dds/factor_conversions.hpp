// IDL <-> core conversions for causal factor vectors.
#pragma once

#include "causal/pipeline/factor_stream.hpp"
#include "causal/estimation/svar_layout.hpp"
#include "causal_twin.h"

#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

namespace causal::dds {

// What a report needs around it to become a CausalFactorBatch message.
struct FactorContext {
  std::string asset_group;
  causal_twin::TimeScale time_scale = causal_twin::SAMPLE_LEVEL;
  std::string feature;                     // condition feature ("" at sample level)
  const estimation::SvarLayout* layout = nullptr;
  std::vector<std::string> channel_names;  // G names
  // CausalFactorBatch.order_confidence / order_source (pipeline::LearnedStructure); NaN / "" = not assessed.
  double order_confidence = std::numeric_limits<double>::quiet_NaN();
  std::string order_source;
};

// One outcome's block: factor_covariance carries report.covariance packed (empty when the report has none,
// e.g. fixed-lag, or when it is not factors.size() square).
void to_outcome_factors(const FactorContext& context, const pipeline::FactorReport& report,
                        causal_twin::OutcomeFactors& out);

// The batches of a list of reports (one per outcome, kind and index, in any order): one batch per
// (kind, sample_index), in the order their first report appears, blocks sorted by outcome. Every report is in
// exactly one batch. A stream reports every outcome at every published index, so each batch has G blocks.
std::vector<causal_twin::CausalFactorBatch> to_causal_factor_batches(const FactorContext& context,
                                                                     const std::vector<pipeline::FactorReport>& reports);

// The wire form of a symmetric d x d covariance: its lower triangle row by row, P(0,0), P(1,0), P(1,1),
// P(2,0), ..., d(d+1)/2 values (the upper triangle is redundant). Throws std::invalid_argument if p is not
// square.
std::vector<double> pack_lower_triangle(const Eigen::MatrixXd& p);
// Inverse of pack_lower_triangle: the symmetric d x d matrix. Returns an empty (0 x 0) matrix when
// packed.size() != d(d+1)/2 or d < 0 (d = 0 with no values gives the valid 0 x 0 matrix too).
Eigen::MatrixXd unpack_lower_triangle(const std::vector<double>& packed, int d);

// One outcome's block of a received CausalFactorBatch with the batch's header, in core types (outcome
// 0-based): what the consumers' assemblers take, one per outcome.
struct FactorMessage {
  std::string asset_group;
  int outcome = 0;
  causal_twin::EstimateKind kind = causal_twin::FILTER;
  causal_twin::TimeScale time_scale = causal_twin::SAMPLE_LEVEL;
  std::string feature;
  std::string outcome_name;
  int channel_count = 0;
  int lag_order = 0;
  std::uint64_t sample_index = 0;
  std::int64_t time_ns = 0;
  std::vector<std::string> factor_names;
  Eigen::VectorXd factors, factor_std;
  Eigen::MatrixXd covariance;  // P_k, symmetric, factors.size() square; empty when the message has none
                               // (fixed-lag) or its factor_covariance has the wrong count
  std::uint64_t innovation_count = 0;
  double innovation_mean = 0.0, nis_mean = 0.0, last_innovation = 0.0, last_innovation_variance = 0.0;
  std::uint64_t rejected_samples = 0;
};

// Empty string when the batch is consistent: channel_count >= 2, at least one block, outcomes strictly
// increasing within 1..channel_count, and in every block equal lengths of names, factors and std and
// factor_covariance empty or d(d+1)/2 values for d = factors.size(). Otherwise names the first problem.
std::string validate_causal_factor_batch(const causal_twin::CausalFactorBatch& in);
// One FactorMessage per block, in the batch's order (call validate_causal_factor_batch() first).
std::vector<FactorMessage> from_causal_factor_batch(const causal_twin::CausalFactorBatch& in);
// The number of outcome blocks a consumer received in a batch (what one message per outcome used to count).
inline std::size_t outcome_blocks(const causal_twin::CausalFactorBatch& in) { return in.outcomes().size(); }

const char* to_string(causal_twin::EstimateKind kind);
const char* to_string(causal_twin::TimeScale scale);

}  // namespace causal::dds
