// IDL conversions for the advisor's results (the one place where they meet the generated types).
#pragma once

#include "advisor.hpp"
#include "causal_twin.h"

namespace causal::recommender {

void to_recommendation(const std::string& asset_group, const std::string& alarm_id, const AdviceItem& item,
                       causal_twin::Recommendation& out);
void to_whatif_reply(const causal_twin::WhatIfRequest& request, const WhatIfAnswer& answer, causal_twin::WhatIfReply& out);

}  // namespace causal::recommender
