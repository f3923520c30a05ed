// The page's alarm actions (acknowledge, shelve, unshelve) to alarm-recommender and its results back
// (result.applied() may be false: refused).
#pragma once

#include "causal_twin.h"
#include "request_bridge.hpp"

namespace causal::web {

using AlarmActionBridge = RequestBridge<causal_twin::AlarmAction, causal_twin::AlarmActionResult>;

}  // namespace causal::web
