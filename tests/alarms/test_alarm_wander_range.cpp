// Quiet inside the range a channel's level came back from while healthy (SignalMonitor::wander_top): a slow
// excursion of +13 % over days that returns is learned once it has come back; the same excursion again is no
// degradation; a monotone rise beyond that range still alarms. Synthetic group of four channels with 1 %
// log-level noise and oracle innovations (synthetic_group.hpp): the truth is how the stream was built.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;
using namespace causal::alarms::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A monotone rise after the wander: to `ratio` over `rows` observations, then held.
struct Rise {
  double ratio;
  int rows;
};

// Log excursion of channel 0 at observation t: two raised-cosine bumps of `peak` over 400 observations (each
// above the +8 % floor for ~170 of them, longer than the 120-observation baseline), then from `rise_at` the
// monotone rise.
double excursion(int t, double peak, int rise_at, Rise rise) {
  for (int t0 : {300, 900})
    if (t >= t0 && t < t0 + 400) return peak * 0.5 * (1.0 - std::cos(2.0 * kPi * (t - t0) / 400.0));
  if (t >= rise_at) return std::log(rise.ratio) * std::min(1.0, static_cast<double>(t - rise_at) / rise.rows);
  return 0.0;
}

std::vector<std::uint64_t> raises_on(const std::vector<AlarmEvent>& ev, int channel) {
  std::vector<std::uint64_t> out;
  for (const auto& e : ev)
    if (e.category == category::kDegradation && e.state == AlarmState::Raised && e.channel == channel) out.push_back(e.index);
  return out;
}

// Degradation alarms of `channel` open after observation `at` (raised minus cleared up to it).
int open_at(const std::vector<AlarmEvent>& ev, int channel, std::uint64_t at) {
  int open = 0;
  for (const auto& e : ev)
    if (e.category == category::kDegradation && e.channel == channel && e.index <= at)
      open += e.state == AlarmState::Raised ? 1 : e.state == AlarmState::Cleared ? -1 : 0;
  return open;
}

}  // namespace

// The rises: +25 % over 100 observations and +40 % over 200. Both pass a step's size (operating_step_ratio,
// +15 %) before the widened floor (+13 % and half the floor) lets them alarm: the level-step rule must not
// absorb them as a settled single channel's step (it did, in 2 and 5 of the 5 seeds, before confirm_step
// left such a channel to its detectors).
TEST(AlarmWanderRange, ReturnedExcursionIsLearnedAndAMonotoneRiseBeyondItAlarms) {
  for (const Rise rise : {Rise{1.25, 100}, Rise{1.4, 200}})
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    cfg.n = 1800;
    cfg.sigma = 0.01;
    cfg.changed = 0;
    cfg.own_change = [&](int t) { return excursion(t, std::log(1.13), 1500, rise) / cfg.sigma; };
    AlarmEngine e("grp", channel_names4(), {}, AlarmParams{});
    const auto ev = run_all(e, make_run(cfg));
    const auto r = raises_on(ev, 0);
    auto in = [&](std::uint64_t a, std::uint64_t b) {
      int n = 0;
      for (auto i : r) n += i >= a && i < b;
      return n;
    };
    // The first excursion is beyond everything the channel showed (the test can fail: it alarms)...
    EXPECT_GT(in(300, 700), 0) << "seed " << seed;
    // ... it came back and its alarms cleared, so the same excursion again is inside the channel's own range.
    EXPECT_EQ(open_at(ev, 0, 899), 0) << "seed " << seed;
    EXPECT_EQ(in(900, 1300), 0) << "seed " << seed;
    // The monotone rise leaves that range (+13 % and half the floor) and is alarmed by the end of its ramp
    // (raised in it, or still open from before), never followed as a level step.
    EXPECT_GT(open_at(ev, 0, static_cast<std::uint64_t>(1500 + rise.rows + 50)), 0) << "seed " << seed << " rise " << rise.ratio;
    for (const auto& e : ev)
      EXPECT_FALSE(e.channel == 0 && e.index >= 1500 && e.category == category::kOperatingChange)
          << "seed " << seed << " rise " << rise.ratio << ": " << e.reason;
  }
}
