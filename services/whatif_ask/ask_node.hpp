// causal-ask's DDS node: one WhatIfRequest out on causal_twin/whatif_request, the matching WhatIfReply in
// from causal_twin/whatif_reply (answered by alarm-recommender from the live condition-level model).
#pragma once

#include "causal/config/exit_codes.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <optional>
#include <string>

namespace causal::ask {

struct AskOptions {
  dds::CommonOptions dds;
  std::string asset_group;
  int channel = 0;                // j, 1-based
  std::optional<double> delta;    // shift in model units (log-level when the estimator logs features)
  std::optional<double> percent;  // or a level change in percent: delta = log(1 + percent / 100)
  bool impulse = false;           // one-snapshot change instead of a sustained one
  double timeout_s = 10.0;
};

// Exit codes of run().
inline constexpr int kAnswered = config::kExitOk;
inline constexpr int kNoAnswer = config::kExitNoPeer;       // no alarm-recommender on the domain, or no reply in time
inline constexpr int kRefused = config::kExitLostOrRefused;  // the recommender answered that it cannot be answered

class AskNode {
 public:
  explicit AskNode(AskOptions options);  // throws std::invalid_argument for an invalid question
  int run();
  void stop() { loop_.stop(); }

 private:
  void print(const causal_twin::WhatIfReply& reply) const;

  AskOptions options_;
  double delta_ = 0.0;
  dds::Participant participant_;
  dds::TypedWriter<causal_twin::WhatIfRequestPubSubType> requests_;
  dds::TypedReader<causal_twin::WhatIfReplyPubSubType> replies_;
  dds::EventLoop loop_;
};

}  // namespace causal::ask
