// IDL conversions for the prognosis (the alarm desk's prognosis lines -> causal_twin::Prognosis, and the decision
// fields of causal_twin::Alarm). The plain-language texts are common/prognosis (prognosis_text.hpp).
#pragma once

#include "causal/advice/alarm_desk.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <string>
#include <vector>

namespace causal::recommender {

// One Prognosis message: the line's channel and level at its observation (index, data time), with its text.
void to_prognosis(const std::string& asset_group, const advice::PrognosisLine& line, double coverage,
                  causal_twin::Prognosis& out);

// The decision fields of a degradation alarm: the next level ahead and the time to it (NaN when unknown).
void set_next_level(const prognosis::ChannelPrognosis& p, causal_twin::Alarm& out);

}  // namespace causal::recommender
