// Gaps, operating changes, escalation on persistence and root-cause re-evaluation (AlarmParams, sections
// "gaps and operating changes", "escalation", "root cause re-evaluation"). Synthetic groups of four
// channels with 2 % log-level noise (synthetic_group.hpp): the truth is how each stream was built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/estimation/state_archive.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;
using namespace causal::alarms::test;

namespace {

AlarmEngine make_engine(const AlarmParams& p = AlarmParams{}) { return AlarmEngine("grp", channel_names4(), {}, p); }

std::vector<AlarmEvent> of_category(const std::vector<AlarmEvent>& ev, const std::string& category) {
  std::vector<AlarmEvent> out;
  for (const auto& e : ev)
    if (e.category == category) out.push_back(e);
  return out;
}

// Multiplies channel c's feature by `ratio` from observation `from` on (a level that steps and stays).
void step_level(std::vector<Observation>& obs, int c, int from, double ratio) {
  for (auto& o : obs)
    if (o.index >= static_cast<std::uint64_t>(from)) o.features(c) *= ratio;
}

}  // namespace

// A 2-day gap after which every level is 18 % higher (the IMS pattern): no degradation alarm, one
// discontinuity event (raised and cleared at once) per channel, at the end of the confirmation window.
TEST(AlarmOperatingChanges, GapWithLevelShiftRebaselinesInsteadOfAlarming) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    auto obs = make_run(cfg);
    for (auto& o : obs) {
      if (o.index < 300) continue;
      o.time_ns += 2LL * 86400 * 1000000000LL;
      for (int c = 0; c < 4; ++c) o.features(c) *= 1.18;
    }
    auto e = make_engine();
    const auto ev = run_all(e, obs);
    EXPECT_TRUE(of_category(ev, category::kDegradation).empty()) << "seed " << seed << ": " << ev.front().reason;
    const auto oc = of_category(ev, category::kOperatingChange);
    ASSERT_EQ(oc.size(), 8u) << "seed " << seed;  // 4 channels x (raised, cleared)
    const AlarmParams p;
    for (const auto& x : oc) {
      EXPECT_EQ(x.kind, kind::kDiscontinuity);
      EXPECT_EQ(x.index, 300u + static_cast<std::uint64_t>(p.confirmation_observations) - 1);
      EXPECT_EQ(x.onset_index, 300u);
      EXPECT_NE(x.reason.find("gap of 2.0 days"), std::string::npos) << x.reason;
    }
  }
}

// The source's discontinuity flag alone (no time gap) starts the same re-baselining.
TEST(AlarmOperatingChanges, FlaggedDiscontinuityRebaselines) {
  SyntheticConfig cfg;
  cfg.seed = 4;
  auto obs = make_run(cfg);
  obs[300].discontinuity = true;
  step_level(obs, 0, 300, 1.25);
  step_level(obs, 2, 300, 0.8);
  auto e = make_engine();
  const auto ev = run_all(e, obs);
  EXPECT_TRUE(of_category(ev, category::kDegradation).empty());
  EXPECT_EQ(of_category(ev, category::kOperatingChange).size(), 8u);
}

// Without a gap: +25 % on one channel at once that stays is not a fault; as only one channel moved it is
// not confirmed as an operating change either: it is followed as a level step (within
// max_absorbed_ratio of its reference). The same +25 % arriving as a ramp that keeps rising is degradation
// and alarms.
TEST(AlarmOperatingChanges, SettledStepIsOperatingChangeRisingStepAlarms) {
  const AlarmParams p;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    auto obs = make_run(cfg);
    step_level(obs, 3, 250, 1.25);
    auto e = make_engine();
    const auto ev = run_all(e, obs);
    EXPECT_TRUE(of_category(ev, category::kDegradation).empty()) << "seed " << seed << ": " << ev.front().reason;
    const auto oc = of_category(ev, category::kOperatingChange);
    ASSERT_EQ(oc.size(), 2u) << "seed " << seed;
    EXPECT_EQ(oc[0].kind, kind::kLevelStep);
    EXPECT_EQ(oc[0].channel, 3);
    EXPECT_EQ(oc[0].state, AlarmState::Raised);
    EXPECT_EQ(oc[1].state, AlarmState::Cleared);
    EXPECT_GE(oc[0].onset_index, 249u);
    EXPECT_LE(oc[0].onset_index, 251u);

    // Same step, then a further rise of 1 % per observation (0.5 sigma): not settled -> feature_drift on
    // channel 3 at the end of the confirmation window, onset at the step, root cause itself.
    SyntheticConfig rising = cfg;
    auto robs = make_run(rising);
    step_level(robs, 3, 250, 1.25);
    for (auto& o : robs)
      if (o.index >= 250) o.features(3) *= std::exp(0.01 * static_cast<double>(o.index - 250));
    auto e2 = make_engine();
    const auto ev2 = run_all(e2, robs);
    const auto deg = of_category(ev2, category::kDegradation);
    ASSERT_FALSE(deg.empty()) << "seed " << seed;
    EXPECT_EQ(deg.front().channel, 3);
    EXPECT_EQ(deg.front().kind, kind::kFeatureDrift);
    EXPECT_EQ(deg.front().root_cause_channel, 3);
    EXPECT_LE(deg.front().onset_index, 251u);
    EXPECT_LE(deg.front().index, 251u + static_cast<std::uint64_t>(p.confirmation_observations));
    EXPECT_NE(deg.front().reason.find("did not settle"), std::string::npos) << deg.front().reason;
    EXPECT_TRUE(of_category(ev2, category::kOperatingChange).empty());
  }
}

// A smaller significant rise (+10 %, below operating_step_ratio) is alarmed at once, as before: at the
// latest when the level window (median of level_window = 5) holds only values after the step and the size
// floor (advisory_ratio, +8 %) has held on it for level_window observations.
TEST(AlarmOperatingChanges, SmallStepAlarmsAtOnce) {
  SyntheticConfig cfg;
  cfg.seed = 2;
  auto obs = make_run(cfg);
  step_level(obs, 0, 300, 1.10);
  auto e = make_engine();
  const auto ev = run_all(e, obs);
  const auto deg = of_category(ev, category::kDegradation);
  ASSERT_FALSE(deg.empty());
  EXPECT_EQ(deg.front().channel, 0);
  EXPECT_LE(deg.front().index, 300u + 2u * static_cast<std::uint64_t>(AlarmParams{}.level_window));
  EXPECT_TRUE(of_category(ev, category::kOperatingChange).empty());
}

// Severity escalates on persistence when escalation_persistence > 1 (the shipped 1 escalates at the median
// of 5's crossing: AlarmLevelEvent in tests/prognosis): a level above the Warning ratio for fewer than
// escalation_persistence observations stays advisory; held longer, it escalates exactly when the count
// is reached.
TEST(AlarmOperatingChanges, EscalationNeedsPersistence) {
  AlarmParams p;
  p.escalation_persistence = 12;
  p.operating_step_ratio = 1e3;  // the rise below is a step: keep it a fault to watch its severity
  SyntheticConfig cfg;
  cfg.seed = 7;
  auto obs = make_run(cfg);
  step_level(obs, 0, 300, 1.12);                       // significant: alarmed at once, advisory
  for (auto& o : obs)                                  // x2.5 (above warning_ratio 2) for 8 observations
    if (o.index >= 350 && o.index < 358) o.features(0) *= 2.5;
  for (auto& o : obs)                                  // x2.5 again from 400 on, to the end
    if (o.index >= 400) o.features(0) *= 2.5;
  auto e = make_engine(p);
  const auto ev = run_all(e, obs);
  std::vector<AlarmEvent> esc;
  for (const auto& x : ev)
    if (x.channel == 0 && x.kind == kind::kFeatureDrift && x.state == AlarmState::Escalated) esc.push_back(x);
  ASSERT_EQ(esc.size(), 1u);
  EXPECT_EQ(esc[0].severity, Severity::Warning);
  // The level window (median of 5) sees the new level from observation 402; 12 consecutive from there.
  EXPECT_EQ(esc[0].index, 402u + static_cast<std::uint64_t>(p.escalation_persistence) - 1);
}

// Root cause re-evaluated: channel 2 (0-based 1) has a short own change (observations 300-329) that channel
// 3 (0-based 2) follows through the link, so channel 3's first alarm names channel 2. From 310 channel 3
// changes on its own and keeps going; once channel 2's trouble is over (its alarms cleared), channel 3's
// alarm is re-attributed to channel 3 itself, republished (Escalated, same id) with the reason and a
// confidence above one half.
TEST(AlarmOperatingChanges, RootCauseReevaluatedWhenNamedRootRecovers) {
  AlarmParams p;
  p.operating_step_ratio = 1e3;
  SyntheticConfig cfg;
  cfg.seed = 11;
  cfg.changed = 1;  // channel 2 drives channel 3 (link 0.8)
  cfg.own_change = [](int t) { return t >= 300 && t < 330 ? 6.0 : 0.0; };  // a short own change
  cfg.changed2 = 2;                                                        // then channel 3's own
  cfg.own_change2 = [](int t) { return t >= 310 ? 6.0 : 0.0; };
  auto e = make_engine(p);
  const auto ev = run_all(e, make_run(cfg));
  const AlarmEvent* first3 = nullptr;
  const AlarmEvent* changed = nullptr;
  for (const auto& x : ev) {
    if (x.channel != 2 || x.category != category::kDegradation) continue;
    if (!first3 && x.state == AlarmState::Raised) first3 = &x;
    if (first3 && x.alarm_id == first3->alarm_id && x.reason.find("Root cause re-evaluated") != std::string::npos)
      changed = &x;
  }
  ASSERT_NE(first3, nullptr);
  EXPECT_EQ(first3->root_cause_channel, 1) << first3->reason;
  EXPECT_GE(first3->root_cause_confidence, 0.0);
  EXPECT_LE(first3->root_cause_confidence, 1.0);
  ASSERT_NE(changed, nullptr) << "the alarm of channel 3 kept root cause channel 2 after channel 2 recovered";
  EXPECT_EQ(changed->root_cause_channel, 2) << changed->reason;
  EXPECT_EQ(changed->state, AlarmState::Escalated);
  EXPECT_GT(changed->root_cause_confidence, 0.5) << changed->reason;
}

// A checkpoint written in the middle of a confirmation window restores it: the rest of the stream gives
// exactly the events of the uninterrupted engine.
TEST(AlarmOperatingChanges, CheckpointDuringConfirmationContinuesExactly) {
  SyntheticConfig cfg;
  cfg.seed = 5;
  auto obs = make_run(cfg);
  for (auto& o : obs)
    if (o.index >= 300) o.time_ns += 86400LL * 1000000000LL;
  step_level(obs, 1, 300, 1.2);
  auto full = make_engine();
  const auto expected = run_all(full, obs);
  ASSERT_FALSE(expected.empty());
  auto a = make_engine();
  std::vector<AlarmEvent> got;
  for (std::size_t i = 0; i < 305; ++i)
    for (auto& x : a.observe(obs[i])) got.push_back(std::move(x));
  causal::estimation::StateWriter w;
  a.save(w);
  causal::estimation::StateReader r(w.bytes());
  auto b = AlarmEngine::restore(r, AlarmParams{});
  for (std::size_t i = 305; i < obs.size(); ++i)
    for (auto& x : b.observe(obs[i])) got.push_back(std::move(x));
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].alarm_id, expected[i].alarm_id);
    EXPECT_EQ(got[i].index, expected[i].index);
    EXPECT_EQ(got[i].reason, expected[i].reason);
  }
}

// A change of load moves every bearing at once (+25 %, no gap): all four are re-baselined with the channel
// whose step started the confirmation, none alarms.
TEST(AlarmOperatingChanges, StepOnAllChannelsAtOnceIsOneOperatingChange) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SyntheticConfig cfg;
    cfg.seed = seed;
    auto obs = make_run(cfg);
    for (int c = 0; c < 4; ++c) step_level(obs, c, 300, 1.25);
    auto e = make_engine();
    const auto ev = run_all(e, obs);
    EXPECT_TRUE(of_category(ev, category::kDegradation).empty()) << "seed " << seed << ": " << ev.front().reason;
    const auto oc = of_category(ev, category::kOperatingChange);
    EXPECT_EQ(oc.size(), 8u) << "seed " << seed;  // 4 channels x (raised, cleared)
    for (const auto& x : oc) EXPECT_EQ(x.kind, kind::kOperatingChange);
  }
}

// A stop (every channel at 10 % of its level for 5 observations: the operating-state gate skips them) and
// a restart at +20 %: the restart is a discontinuity, re-baselined and said, not alarmed.
TEST(AlarmOperatingChanges, RestartAfterStopRebaselines) {
  SyntheticConfig cfg;
  cfg.seed = 8;
  auto obs = make_run(cfg);
  for (auto& o : obs) {
    if (o.index >= 300 && o.index < 305) o.features *= 0.1;
    if (o.index >= 305) o.features *= 1.2;
  }
  auto e = make_engine();
  const auto ev = run_all(e, obs);
  EXPECT_EQ(e.not_running_observations(), 5u);
  EXPECT_TRUE(of_category(ev, category::kDegradation).empty()) << ev.front().reason;
  const auto oc = of_category(ev, category::kOperatingChange);
  ASSERT_EQ(oc.size(), 8u);
  for (const auto& x : oc) {
    EXPECT_EQ(x.kind, kind::kDiscontinuity);
    EXPECT_EQ(x.onset_index, 305u);
    EXPECT_NE(x.reason.find("a stop"), std::string::npos) << x.reason;
  }
}
