// The identity fields of a factor message for the assembler tests (one outcome block of a CausalFactorBatch):
// which stream, which outcome of how many channels, which sample. The caller adds the factors, their names and
// the innovation statistics.
#pragma once

#include "causal/dds/factor_conversions.hpp"

#include <cstdint>
#include <string>

namespace causal::test {

// The stream a message belongs to: asset group, time scale, estimate kind and (condition level) feature.
struct FactorStreamId {
  std::string group;
  causal_twin::TimeScale scale;
  causal_twin::EstimateKind kind;
  std::string feature;
};

// Outcome k (0-based, named outcome_name) of `channels` channels at lag order `lags`, sample `index` at time_ns.
inline dds::FactorMessage factor_message_head(const FactorStreamId& id, int k, const std::string& outcome_name,
                                              int channels, int lags, std::uint64_t index, std::int64_t time_ns) {
  dds::FactorMessage m;
  m.asset_group = id.group;
  m.outcome = k;
  m.kind = id.kind;
  m.time_scale = id.scale;
  m.feature = id.feature;
  m.outcome_name = outcome_name;
  m.channel_count = channels;
  m.lag_order = lags;
  m.sample_index = index;
  m.time_ns = time_ns;
  return m;
}

}  // namespace causal::test
