// causal-approve's DDS node: an operator's approval of one recommended lever, published as one Intervention on
// causal_twin/intervention. It publishes only what it is told: the recommendation named by --recommendation (read
// from causal_twin/recommendation, where alarm-recommender keeps its advice), for the group named by --group,
// approved by --user; nothing else is ever published, and without this act (or twin-web's approve button) no
// recommendation becomes an intervention.
#pragma once

#include "causal/config/exit_codes.hpp"
#include "causal/dds/approval.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace causal::approve {

struct ApproveOptions {
  dds::CommonOptions dds;
  std::string asset_group;
  std::string recommendation_id;
  std::string user;
  std::optional<std::uint64_t> start_index;  // default: the group's latest snapshot + lead
  std::uint64_t lead = 3;                    // snapshots between the source's latest one seen and the start
  std::optional<std::uint64_t> duration;     // default: the recommendation's horizon, at least 12
  std::vector<std::string> wait_for;         // participants whose intervention readers must be matched
  double timeout_s = 15.0;
};

// Exit codes of run().
inline constexpr int kPublished = config::kExitOk;
inline constexpr int kNotDelivered = config::kExitNoPeer;   // recommendation not found, no reader, or not acknowledged in time
inline constexpr int kNotApprovable = config::kExitLostOrRefused;  // the recommendation is not a lever that can be applied


class ApproveNode {
 public:
  explicit ApproveNode(ApproveOptions options);  // throws std::invalid_argument for invalid options
  int run();
  void stop() { loop_.stop(); }

 private:
  // Reads the transient-local advice and condition vectors until the recommendation is found and the source's
  // current index is known (from its condition inputs, at most 3 s after the advice), bounded by the deadline.
  std::optional<causal_twin::Recommendation> find_recommendation(std::chrono::steady_clock::time_point deadline);
  bool readers_ready(std::chrono::steady_clock::time_point deadline);

  ApproveOptions options_;
  dds::Participant participant_;
  dds::TypedReader<causal_twin::RecommendationPubSubType> recommendations_;
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> conditions_;
  // The source's own condition inputs (volatile: only what is published from now on): the plant's current
  // snapshot index, ahead of the estimator's output when the estimator is behind.
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> inputs_;
  dds::TypedWriter<causal_twin::InterventionPubSubType> interventions_;
  dds::EventLoop loop_;
  std::optional<std::uint64_t> latest_index_;
  bool input_seen_ = false;
  std::int64_t latest_time_ns_ = 0, cadence_ns_ = 0;
};

}  // namespace causal::approve
