// The prognosis in plain words (hours and UTC), shared by alarm-recommender's log, its Prognosis messages and the
// operator's AssetStatus line. Std only: the IDL filling (to_prognosis, set_next_level) stays at the DDS edge.
#pragma once

#include "causal/prognosis/alarm_prognosis.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace causal::prognosis {

// Data time `hours` after time_ns (0 when hours is not finite: no time to give).
std::int64_t eta_ns(std::int64_t time_ns, double hours);

// The channel's name (its 1-based number when the names do not reach it): what Prognosis.channel_name carries.
std::string channel_label(const std::vector<std::string>& channel_names, int channel);

// "bearing1 reaches critical (4x its baseline) in 12.3 h (90 % interval 8.1-20.4 h): 2004-02-19 04:10 UTC
// (02:00-14:30 UTC)"; "... has reached ..."; "... time to ... unknown: <why>".
std::string prognosis_text(const std::string& channel_name, const ChannelPrognosis& p, std::int64_t time_ns,
                           double coverage);

// The operator's short form (AssetStatus.prognosis_text), rounded so it changes when the forecast does, not at
// every snapshot: "bearing1: warning in ~12 h (6-30 h), ~2004-02-19 18:00 UTC"; "bearing1: critical reached";
// "bearing1: warning: unknown (<why>)"; end_of_life reads "end of life".
std::string status_prognosis_text(const std::string& channel_name, const ChannelPrognosis& p, std::int64_t time_ns);

}  // namespace causal::prognosis
