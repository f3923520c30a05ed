// What-if questions from the page to alarm-recommender and its replies back (reply.ok() may be false: a refusal).
#pragma once

#include "causal_twin.h"
#include "request_bridge.hpp"

namespace causal::web {

using WhatIfBridge = RequestBridge<causal_twin::WhatIfRequest, causal_twin::WhatIfReply>;

}  // namespace causal::web
