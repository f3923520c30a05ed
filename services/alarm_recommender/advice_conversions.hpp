// IDL conversions for the advisor's results (the one place where they meet the generated types).
#pragma once

#include "advice_names.hpp"
#include "causal_twin.h"

#include <cmath>
#include <cstdint>
#include <string>

namespace causal::recommender {

// What a Recommendation carries besides the advisor's numbers: the event it answers and the decision.
struct RecommendationContext {
  std::string asset_group;
  std::string alarm_id;
  std::string id_prefix;            // recommendation_id = id_prefix + "/" + rank
  std::uint64_t sample_index = 0;   // the alarm event's index
  std::string action;
  std::string action_kind;          // "act_on_asset", "upstream_lever", "monitor"
  int act_on_channel = -1;          // 0-based; -1 none
  std::string act_on_name;
  double horizon_hours = NAN;
  double order_confidence = NAN;
  std::string order_source;
};

void to_recommendation(const RecommendationContext& context, const AdviceItem& item, causal_twin::Recommendation& out);
void to_whatif_reply(const causal_twin::WhatIfRequest& request, const WhatIfAnswer& answer, causal_twin::WhatIfReply& out);

}  // namespace causal::recommender
