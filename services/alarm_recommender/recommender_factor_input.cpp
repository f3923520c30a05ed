// alarm-recommender: the causal factors in, one message per batch (causal_twin/causal_factors) or one per input
// (causal_twin/causal_factor_sets, unpacked in order): both go through the same per-batch handling.
#include "recommender_node.hpp"

#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/factor_sets.hpp"

#include <spdlog/spdlog.h>

namespace causal::recommender {

std::size_t RecommenderNode::take_factors(std::vector<AssembledObservation>& into) {
  std::size_t n = 0;
  // One batch, whether it came alone or in a set (output.factor_messages): the same handling, in order.
  const auto on_batch = [&](const causal_twin::CausalFactorBatch& f) {
    if (const auto problem = dds::validate_causal_factor_batch(f); !problem.empty()) {
      ++invalid_msgs_;
      spdlog::warn("causal factors from '{}' refused: {}", f.asset_group(), problem);
      return;
    }
    ++factors_received_;  // messages (batches), as the estimator counts what it sent
    if (f.time_scale() == causal_twin::CONDITION_LEVEL && f.kind() == causal_twin::FILTER) {
      desk_.set_order_trust(f.asset_group(), OrderTrust{f.order_confidence(), f.order_source()});
    }
    // One outcome at a time: the assembler also takes partial batches and keeps its per-index checks.
    for (const auto& m : dds::from_causal_factor_batch(f)) assembler_.add_factors(m, into);
  };
  n += factors_.take_all_and_states([&](const causal_twin::CausalFactorBatch& f, const auto& info) {
    // Condition-level factors carry the snapshot index (the health alarm's id names the last one).
    if (f.time_scale() == causal_twin::CONDITION_LEVEL) {
      health_.on_sample(f.asset_group(), f.sample_index(), info);
    } else {
      health_.on_sample(f.asset_group(), info);
    }
    on_batch(f);
  }, [this](const auto& info) { health_.on_state(info); }, loop_.stop_flag());
  if (!factor_sets_) return n;
  n += factor_sets_->take_all_and_states([&](const causal_twin::CausalFactorSet& s, const auto& info) {
    ++factor_set_counts_.received;
    if (const std::string problem = dds::factor_set_problem(s); !problem.empty()) {
      ++factor_set_counts_.refused;
      spdlog::warn("causal factor set of '{}' refused: {}", s.asset_group(), problem);
      return;
    }
    if (s.time_scale() == causal_twin::CONDITION_LEVEL) {
      health_.on_sample(s.asset_group(), s.batches().back().sample_index(), info);
    } else {
      health_.on_sample(s.asset_group(), info);
    }
    for (const auto& f : s.batches()) {
      ++factor_set_counts_.batches;
      on_batch(f);
    }
  }, [this](const auto& info) { health_.on_state(info); }, loop_.stop_flag());
  return n;
}

}  // namespace causal::recommender
