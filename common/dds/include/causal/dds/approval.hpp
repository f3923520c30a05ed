// What an approval of one recommendation is, shared by causal-approve and twin-web's approve button so both
// publish the same Intervention for the same act (same fields, same request id): IDL types only, no DDS entities.
#pragma once

#include "causal_twin.h"

#include <cstdint>
#include <optional>
#include <string>

namespace causal::dds {

// Who approves what: the group the operator means, the operator, and an optional hold (snapshots).
struct ApprovalAct {
  std::string asset_group;
  std::string user;
  std::optional<std::uint64_t> duration;  // default: the recommendation's horizon, at least 12
};

// The intervention an approval of `rec` makes. Empty `why` when approvable.
struct Approval {
  causal_twin::Intervention intervention;
  std::string why;  // non-empty: not approvable, and why
};
Approval make_approval(const causal_twin::Recommendation& rec, const ApprovalAct& act, std::uint64_t start,
                       std::int64_t start_time_ns, std::int64_t now_ns);

// The start time of snapshot `start` from the latest one seen (its index and time) and the cadence between two
// consecutive snapshots; 0 (unknown) when the cadence is not known or `start` lies before the latest.
std::int64_t start_time_of(std::uint64_t start, std::optional<std::uint64_t> latest_index, std::int64_t latest_time_ns,
                           std::int64_t cadence_ns);

}  // namespace causal::dds
