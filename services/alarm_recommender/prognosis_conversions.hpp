// IDL conversions for the prognosis (causal_prognosis results -> causal_twin::Prognosis and the decision fields
// of causal_twin::Alarm), with the plain-language text in hours and UTC.
#pragma once

#include "causal/prognosis/alarm_prognosis.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <string>
#include <vector>

namespace causal::recommender {

// One Prognosis message: p's channel and level at observation `sample_index` (data time time_ns).
void to_prognosis(const std::string& asset_group, const std::vector<std::string>& channel_names,
                  const prognosis::ChannelPrognosis& p, std::uint64_t sample_index, std::int64_t time_ns,
                  double coverage, causal_twin::Prognosis& out);

// "bearing1 reaches critical (4x its baseline) in 12.3 h (90 % interval 8.1-20.4 h): 2004-02-19 04:10 UTC
// (02:00-14:30 UTC)"; "... has reached ..."; "... time to ... unknown: <why>".
std::string prognosis_text(const std::string& channel_name, const prognosis::ChannelPrognosis& p, std::int64_t time_ns,
                           double coverage);

// The operator's short form (AssetStatus.prognosis_text), rounded so it changes when the forecast does, not at
// every snapshot: "bearing1: warning in ~12 h (6-30 h), ~2004-02-19 18:00 UTC"; "bearing1: critical reached";
// "bearing1: warning: unknown (<why>)"; end_of_life reads "end of life".
std::string status_prognosis_text(const std::string& channel_name, const prognosis::ChannelPrognosis& p,
                                  std::int64_t time_ns);

// The decision fields of a degradation alarm: the next level ahead and the time to it (NaN when unknown).
void set_next_level(const prognosis::ChannelPrognosis& p, causal_twin::Alarm& out);

}  // namespace causal::recommender
