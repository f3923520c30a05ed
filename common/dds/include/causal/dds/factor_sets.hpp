// Causal factors as one message per input (causal_twin/causal_factor_sets, CausalFactorSet) beside one message
// per batch (causal_twin/causal_factors, CausalFactorBatch): the estimator writes one of the two
// (estimator.yaml output.factor_messages), every reader takes both. A reader hands each batch of a set to the
// same per-batch handling, in the set's order, so what it records or computes is the same as if the batches
// had come one by one (the estimator puts them in the order it would have written them).
#pragma once

#include "causal/dds/participant.hpp"
#include "causal/dds/sample_limits.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace causal::dds {

// The layout version a writer puts in CausalFactorSet::version and the only one a reader takes.
inline constexpr std::uint32_t kFactorSetVersion = 1;
// At most this many batches in one set (the IDL's bound). One input usually makes two per level (the filter's and
// the fixed-lag smoother's); one that made more (publish_every below the frame, the replay after start-up tuning)
// is written as consecutive sets of at most this many, in order.
inline constexpr std::size_t kFactorSetMaxBatches = kMaxFactorSetBatches;

// "" when the set can be unpacked; else why it is refused (then none of its batches is used): another layout
// version, no batch, or a batch of another asset group or time scale than the set's key (a reader keyed by the
// set would file it under the wrong instance).
inline std::string factor_set_problem(const causal_twin::CausalFactorSet& s) {
  if (s.version() != kFactorSetVersion) {
    return "layout version " + std::to_string(s.version()) + " (this reader takes " +
           std::to_string(kFactorSetVersion) + ")";
  }
  if (s.batches().empty()) return "no batch in the set";
  for (const auto& b : s.batches()) {
    if (b.asset_group() != s.asset_group() || b.time_scale() != s.time_scale()) {
      return "a batch of asset group '" + b.asset_group() + "' or another time scale than the set's";
    }
  }
  return "";
}

// What a reader of sets saw, for its summary line (`summary topic=causal_twin/causal_factor_sets ...`).
struct FactorSetCounts {
  std::uint64_t received = 0;  // set messages taken
  std::uint64_t batches = 0;   // batches in them, handed on
  std::uint64_t refused = 0;   // sets refused whole (factor_set_problem)
};

// The set reader every factor reader has beside its batch reader (the same reader profile: a profile is per
// endpoint, not per topic).
using FactorSetReader = TypedReader<causal_twin::CausalFactorSetPubSubType>;

// The set reader, or null on a secured participant whose permissions do not name causal_twin/causal_factor_sets
// (an identity issued before the topic existed): then this process reads the batches only, as before, and says
// so once (a warning naming the topic). Unsecured, a failure is an error as for any reader.
std::unique_ptr<FactorSetReader> make_factor_set_reader(Participant& participant);
inline std::size_t matched_writers(const std::unique_ptr<FactorSetReader>& reader) {
  return reader ? reader->matched_writers() : 0;
}

// Hands every usable set's batches to on_batch(const CausalFactorBatch&, const SampleInfo&) in order;
// on_refused(const CausalFactorSet&, const std::string& problem) for a set refused whole. Returns the sets taken.
template <typename OnBatch, typename OnRefused>
std::size_t take_factor_sets(const std::unique_ptr<FactorSetReader>& reader, FactorSetCounts& counts,
                             OnBatch&& on_batch, OnRefused&& on_refused, const std::atomic<bool>* stop = nullptr) {
  if (!reader) return 0;
  return reader->take_all(
      [&](const causal_twin::CausalFactorSet& s, const eprosima::fastdds::dds::SampleInfo& info) {
        ++counts.received;
        if (const std::string problem = factor_set_problem(s); !problem.empty()) {
          ++counts.refused;
          on_refused(s, problem);
          return;
        }
        for (const auto& b : s.batches()) {
          ++counts.batches;
          on_batch(b, info);
        }
      },
      stop);
}

}  // namespace causal::dds
