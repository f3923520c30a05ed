// The operator's samples the grant tests send to alarm-recommender: make(group, n) builders (the form
// switch_against_recommender and the group-limited writers call) for a what-if question and an acknowledgement,
// the n-th with request id <prefix><n>.
#pragma once

#include "causal_twinPubSubTypes.h"

#include <cstdint>
#include <string>

namespace causal::test::security {

// "What if channel 1 rose by 0.5, sustained?" about `group`.
inline auto whatif_questions(const std::string& prefix) {
  return [prefix](const std::string& group, std::uint64_t n) {
    causal_twin::WhatIfRequest r;
    r.request_id(prefix + std::to_string(n));
    r.asset_group(group);
    r.intervene_channel(1);
    r.delta(0.5);
    r.sustained(true);
    return r;
  };
}

// `user` acknowledges the group's alarm on channel 1.
inline auto acknowledgements(const std::string& prefix, const std::string& user) {
  return [prefix, user](const std::string& group, std::uint64_t n) {
    causal_twin::AlarmAction a;
    a.request_id(prefix + std::to_string(n));
    a.asset_group(group);
    a.alarm_id(group + "/1/feature_drift/1");
    a.action(causal_twin::ACKNOWLEDGE);
    a.user_name(user);
    a.time_ns(1'800'000'000'000'000'000LL);
    return a;
  };
}

}  // namespace causal::test::security
