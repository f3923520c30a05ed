// An IMS variant (tests/support/ims_variants*.hpp) as the condition series the services' chain reads:
// feature meanabs, one row per snapshot, a discontinuity where the gap to the previous snapshot is over the
// shipped gap_multiple of the 10-minute snapshot period.
#pragma once

#include <algorithm>
#include <cstddef>

#include "causal/alarms/alarm_pipeline.hpp"
#include "ims_variants.hpp"

namespace causal::alarms::test {

inline ConditionSeries series_of(const causal::testing::Variant& v) {
  ConditionSeries s;
  s.channel_names = v.channel_names;
  s.time_ns = v.time_ns;
  s.values = v.values;
  s.feature = "meanabs";
  const double gap = AlarmParams{}.gap_multiple * 600e9;
  for (std::size_t i = 0; i < v.time_ns.size(); ++i) {
    s.index.push_back(i);
    s.discontinuity.push_back(i == 0 || static_cast<double>(v.time_ns[i] - v.time_ns[i - 1]) > gap);
  }
  return s;
}

// Whether channel c is one the variant makes fail (its truth).
inline bool failing(const causal::testing::Variant& v, int c) {
  return std::find(v.failing_channels.begin(), v.failing_channels.end(), c) != v.failing_channels.end();
}

}  // namespace causal::alarms::test
