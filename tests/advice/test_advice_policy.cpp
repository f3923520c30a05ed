// The decision published with every degradation alarm event (services/alarm_recommender/advice_policy.hpp):
// act on the failing asset, never offer a failing asset as a lever to help a healthier one, claim a lever
// only with a reliable, known-width effect on a trusted causal order.
#include "causal/advice/advice_policy.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace causal::advice;
using causal::alarms::AlarmEvent;
using causal::alarms::Severity;

AlarmEvent open_alarm(int channel, Severity s) {
  AlarmEvent e;
  e.channel = channel;
  e.severity = s;
  return e;
}

AlarmSituation situation(int target, int root, Severity s) {
  AlarmSituation a;
  a.asset_group = "ims2";
  a.channel_names = {"bearing1", "bearing2", "bearing3", "bearing4"};
  a.target = target;
  a.root_cause = root;
  a.severity = s;
  a.open_alarms = {open_alarm(target, s)};
  a.snapshot_hours = 1.0 / 6.0;
  a.time_ns = 1076900000LL * 1000000000LL;  // 2004-02-16
  return a;
}

// A candidate "reduce `lever` back to its baseline" with the effect on the target in percent.
AdviceItem candidate(int target, int lever, double pct, double lo, double hi, bool reliable) {
  AdviceItem c;
  c.target = target;
  c.intervene = lever;
  c.delta = std::log(0.8);
  c.reduction = "20.0 %";
  c.effect = std::log1p(pct / 100.0);
  c.percent = pct;
  c.percent_lower = lo;
  c.percent_upper = hi;
  c.coverage = 0.9;
  c.reliable = reliable;
  c.diag.kind = "horizon";
  c.diag.horizon_snapshots = 12;
  c.summary = "after 12 snapshots (2.0 h): ...";
  return c;
}

const OrderTrust kTrusted{0.95, "learned"};
const ActionCatalogue kCatalogue = ActionCatalogue::rolling_bearing_defaults();
const PolicyParams kPolicy;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(AdvicePolicy, RootCauseItselfActsOnTheAssetWithTheCataloguesActions) {
  // The only candidate's interval includes "no change": no lever, act on bearing1 itself.
  const Decision d = decide(situation(0, 0, Severity::Warning), {candidate(0, 2, -30, -50, 5, false)}, "", kTrusted,
                            kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "act_on_asset");
  EXPECT_EQ(d.act_on, 0);
  EXPECT_TRUE(contains(d.action, "Act on bearing1")) << d.action;
  EXPECT_TRUE(contains(d.action, "plan its replacement")) << d.action;  // the warning actions
  ASSERT_EQ(d.items.size(), 1u);
  EXPECT_EQ(d.items[0].intervene, 0);
  EXPECT_EQ(d.items[0].action, d.action);
}

TEST(AdvicePolicy, NeverReducesAFailingRootCauseToHelpAHealthierAsset) {
  // Alarm (advisory) on bearing3, root cause bearing1 which has a warning open: act on bearing1.
  AlarmSituation s = situation(2, 0, Severity::Advisory);
  s.open_alarms.push_back(open_alarm(0, Severity::Warning));
  const Decision d = decide(s, {candidate(2, 0, -30, -50, -10, true)}, "", kTrusted, kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "act_on_asset");
  EXPECT_EQ(d.act_on, 0);
  EXPECT_TRUE(contains(d.action, "Act on bearing1 (root cause of the advisory alarm on bearing3)")) << d.action;
  EXPECT_FALSE(contains(d.action, "Reduce bearing1")) << d.action;
  for (const auto& item : d.items) EXPECT_FALSE(contains(item.text, "Reduce bearing1")) << item.text;
}

TEST(AdvicePolicy, AFailingCandidateIsNeverALeverButTheAssetToActOn) {
  // Root unknown; the only reliable candidate (bearing1) has a worse alarm open: act on bearing1 as an asset,
  // quoting what fixing it does for bearing3; never "reduce bearing1" to help bearing3.
  AlarmSituation s = situation(2, -1, Severity::Advisory);
  s.open_alarms.push_back(open_alarm(0, Severity::Critical));
  const Decision d = decide(s, {candidate(2, 0, -30, -50, -10, true)}, "", kTrusted, kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "act_on_asset");
  EXPECT_EQ(d.act_on, 0);
  EXPECT_TRUE(contains(d.action, "Act on bearing1")) << d.action;
  EXPECT_FALSE(contains(d.items[0].text, "Reduce bearing1")) << d.items[0].text;
  EXPECT_TRUE(contains(d.items[0].text, "bearing1 drives bearing3 and is failing itself")) << d.items[0].text;
  // Not claimable (untrusted order): act on bearing3 itself, bearing1 never named as a lever.
  const Decision u = decide(s, {candidate(2, 0, -30, -50, -10, true)}, "", OrderTrust{0.1, "untrusted"}, kCatalogue,
                            kPolicy);
  EXPECT_EQ(u.act_on, 2);
  EXPECT_FALSE(contains(u.items[0].text, "Reduce bearing1")) << u.items[0].text;
}

TEST(AdvicePolicy, OwnRootCauseAttributionDoesNotHideAReliableHealthyLever) {
  // The alarm engine names bearing1 its own root cause, yet a healthy bearing2 is a claimable lever.
  const Decision d = decide(situation(0, 0, Severity::Advisory), {candidate(0, 1, -30, -50, -10, true)}, "", kTrusted,
                            kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "upstream_lever");
  EXPECT_EQ(d.act_on, 1);
}

TEST(AdvicePolicy, AReliableHealthyUpstreamLeverOnATrustedOrderIsClaimed) {
  AlarmSituation s = situation(0, 1, Severity::Warning);  // root bearing2, not alarmed itself
  const Decision d = decide(s, {candidate(0, 1, -30, -50, -10, true)}, "", kTrusted, kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "upstream_lever");
  EXPECT_EQ(d.act_on, 1);
  EXPECT_TRUE(contains(d.action, "Reduce bearing2 by 20.0 %")) << d.action;
  EXPECT_TRUE(contains(d.action, "-30.0 %")) << d.action;
  EXPECT_TRUE(contains(d.action, "(2.0 h, by 2004-02-16")) << d.action;  // hours and a date
  EXPECT_TRUE(d.items[0].reliable);
}

TEST(AdvicePolicy, ALinkThatCameWithTheFaultIsNoLever) {
  // Both bearings rose at once from their own causes: the time-varying model now links them, the healthy
  // reference model did not (-3 % then). A common cause explains that as well: act on the alarmed asset.
  AlarmSituation s = situation(0, 1, Severity::Warning);
  AdviceItem c = candidate(0, 1, -30, -50, -10, true);
  c.reference = "appeared";
  c.reference_percent = -3.0;
  const Decision d = decide(s, {c}, "", kTrusted, kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "act_on_asset");
  EXPECT_EQ(d.act_on, 0);
  EXPECT_TRUE(contains(d.note, "was not in the healthy model: it came with the fault")) << d.note;
  c.reference = "held";  // the same link before the fault: a lever
  EXPECT_EQ(decide(s, {c}, "", kTrusted, kCatalogue, kPolicy).kind, "upstream_lever");
  c.reference = "none";  // no reference yet (a group's first model): decided as before
  EXPECT_EQ(decide(s, {c}, "", kTrusted, kCatalogue, kPolicy).kind, "upstream_lever");
}

TEST(AdvicePolicy, NoLeverClaimOnAnUntrustedOrUnassessedOrder) {
  AlarmSituation s = situation(0, 1, Severity::Warning);
  const auto c = candidate(0, 1, -30, -50, -10, true);
  for (const OrderTrust& t : {OrderTrust{0.6, "learned"}, OrderTrust{0.95, "untrusted"}, OrderTrust{}}) {
    const Decision d = decide(s, {c}, "", t, kCatalogue, kPolicy);
    EXPECT_EQ(d.kind, "act_on_asset") << t.source;
    EXPECT_EQ(d.act_on, 0);
    EXPECT_TRUE(contains(d.items[0].text, "no lever claim")) << d.items[0].text;
  }
  // A configured graph is trusted whatever the learned stability.
  EXPECT_EQ(decide(s, {c}, "", OrderTrust{NAN, "configured"}, kCatalogue, kPolicy).kind, "upstream_lever");
  // The documented level is the boundary.
  EXPECT_EQ(decide(s, {c}, "", OrderTrust{0.8, "learned"}, kCatalogue, kPolicy).kind, "upstream_lever");
  EXPECT_EQ(decide(s, {c}, "", OrderTrust{0.79, "learned"}, kCatalogue, kPolicy).kind, "act_on_asset");
}

TEST(AdvicePolicy, AnIntervalWiderThanAFactorOfTenIsEffectUnknownAndNoLever) {
  AlarmSituation s = situation(0, 1, Severity::Warning);
  // -60 % .. +687 %: level factor 7.87 / 0.4 = 19.7 > 10, even though "reliable" came in.
  const Decision d = decide(s, {candidate(0, 1, 100, -60, 687, true)}, "", kTrusted, kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "act_on_asset");
  EXPECT_TRUE(contains(d.items[0].text, "effect unknown")) << d.items[0].text;
  EXPECT_FALSE(contains(d.items[0].text, "687")) << d.items[0].text;
  // Factor 9.5: the numbers are given.
  const Decision ok = decide(s, {candidate(0, 1, -40, -50, 375, true)}, "", kTrusted, kCatalogue, kPolicy);
  EXPECT_EQ(ok.kind, "upstream_lever");
}

TEST(AdvicePolicy, EveryDecisionHasAnAction) {
  // No model at all: still an action on the alarmed asset, with the catalogue's critical actions.
  const Decision d = decide(situation(3, -1, Severity::Critical), {}, "no condition-level causal model yet", kTrusted,
                            kCatalogue, kPolicy);
  EXPECT_EQ(d.kind, "act_on_asset");
  EXPECT_TRUE(contains(d.action, "Act on bearing4 (critical alarm): replace it")) << d.action;
  EXPECT_TRUE(contains(d.items[0].text, "no condition-level causal model yet")) << d.items[0].text;
}

TEST(AdvicePolicy, HoursInHumanUnits) {
  EXPECT_EQ(hours_text(2.0), "2.0 h");
  EXPECT_EQ(hours_text(72.0), "3.0 days");
  EXPECT_EQ(hours_text(NAN), "?");
}

}  // namespace
