// Input lost before the engine vs a pause of the recording (not installed; part of AlarmEngine's state).
//
// A source that numbers its observations consecutively (a snapshot index: every step 1) and then skips
// indices did not pause: the twin lost those observations on the way (a restart beyond a backlog, the network).
// That is no change of the machine: it is reported as a HEALTH event "input_lost" naming the missing range,
// and the time it spans is no recording gap (AlarmEngine::Impl::is_discontinuity). A time jump between
// consecutive indices stays what it was: the recording paused (a discontinuity, re-baselined after it).
//
// Whether the source numbers consecutively is learned from the steps themselves: most positive index steps
// so far were 1. Sample-level publications (indices step by a publication's samples) and sub-sampled series
// (every 4th snapshot) never qualify, so their larger steps are never taken for a loss.
#pragma once

#include <cstdint>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::alarms::detail {

// Observations first..last never reached the engine; the last one it saw before them was at since_ns.
struct LostRange {
  std::uint64_t count = 0;  // 0: nothing lost
  std::uint64_t first = 0, last = 0;
  std::int64_t since_ns = 0;
};

struct IndexContinuity {
  bool has_last = false;
  std::uint64_t last_index = 0;
  std::int64_t last_time_ns = 0;
  std::uint64_t unit_steps = 0;   // positive index steps of exactly 1
  std::uint64_t other_steps = 0;  // positive index steps larger than 1
  std::uint64_t losses = 0;       // missing ranges reported (the input_lost event ids count them)
  std::uint64_t lost = 0;         // observations missing in them

  // The observations missing right before this one (none when it continues the last one, or when the source
  // is not known to number consecutively); then remembers it and counts the loss.
  LostRange step(std::uint64_t index, std::int64_t time_ns);
};

void save(estimation::StateWriter& out, const IndexContinuity& c);
void restore(estimation::StateReader& in, IndexContinuity& c);

}  // namespace causal::alarms::detail
