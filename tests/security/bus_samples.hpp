// Valid samples the security tests put on the bus and then change (fuzz_corpus.hpp's malformed ones, the intruder's
// fakes): built once, so that a field added to a topic type is filled in one place.
#pragma once

#include "causal_twinPubSubTypes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace causal::test::security {

// A frame of four bearing channels b1..b4 at 20 kHz, `samples_per_channel` samples of 0.5 each, starting a record.
inline causal_twin::VibrationFrame four_bearing_frame(const std::string& group, std::uint32_t samples_per_channel) {
  causal_twin::VibrationFrame f;
  f.asset_group(group);
  f.sample_rate_hz(20000.0);
  f.channel_names({"b1", "b2", "b3", "b4"});
  f.samples_per_channel(samples_per_channel);
  f.samples(std::vector<double>(4 * static_cast<std::size_t>(samples_per_channel), 0.5));
  f.discontinuity(true);
  return f;
}

}  // namespace causal::test::security
