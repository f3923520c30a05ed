// twin-web's state (services/twin_web/twin_state.hpp), its JSON and the what-if bridge, against hand-built
// messages and hand-computed expectations: no DDS entities.
#include "twin_state.hpp"
#include "whatif_bridge.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <thread>

using causal::web::StateLimits;
using causal::web::TwinState;
using causal::web::WhatIfBridge;
using nlohmann::json;

namespace {

constexpr std::int64_t kMinute = 60LL * 1000000000LL;

causal_twin::ConditionVector vec(std::uint64_t index, std::vector<double> values,
                                 std::vector<std::string> names = {"a", "b", "c"}) {
  causal_twin::ConditionVector v;
  v.asset_group("g");
  v.feature("rms");
  v.snapshot_index(index);
  v.time_ns(static_cast<std::int64_t>(index) * 10 * kMinute);
  v.channel_names(std::move(names));
  v.values(std::move(values));
  return v;
}

// A condition-level filter batch with one outcome block (the estimator sends all G; one is enough here).
causal_twin::CausalFactorBatch factors(std::uint16_t outcome, std::uint64_t index, std::vector<std::string> names,
                                       std::vector<double> values, std::vector<double> stddev) {
  causal_twin::CausalFactorBatch f;
  f.asset_group("g");
  f.kind(causal_twin::FILTER);
  f.time_scale(causal_twin::CONDITION_LEVEL);
  f.channel_count(3);
  f.lag_order(1);
  f.sample_index(index);
  causal_twin::OutcomeFactors o;
  o.outcome(outcome);
  o.factor_names(std::move(names));
  o.factors(std::move(values));
  o.factor_std(std::move(stddev));
  f.outcomes().push_back(std::move(o));
  return f;
}

causal_twin::Alarm alarm(const std::string& id, causal_twin::AlarmState state, std::uint64_t index,
                         std::int64_t raised_time_ns) {
  causal_twin::Alarm a;
  a.alarm_id(id);
  a.asset_group("g");
  a.channel(1);
  a.channel_name("a");
  a.state(state);
  a.severity(causal_twin::WARNING);
  a.sample_index(index);
  a.raised_time_ns(raised_time_ns);
  a.root_cause_channel(2);
  a.root_cause_name("b");
  a.reason("because");
  return a;
}

json parse(const TwinState& s) { return json::parse(*s.json()); }

}  // namespace

TEST(TwinState, TrendKeepsIndexOrderAndCountsDuplicatesAndRefusals) {
  TwinState s;
  s.on_condition(vec(0, {1, 2, 3}));
  s.on_condition(vec(2, {7, 8, 9}));
  s.on_condition(vec(1, {4, 5, 6}));        // late: inserted in order
  s.on_condition(vec(1, {4, 5, 6}));        // re-sent after a restart
  s.on_condition(vec(3, {1, NAN, 3}));      // non-finite: refused
  s.on_condition(vec(3, {1, INFINITY, 3}));
  s.on_condition(vec(4, {1, 2}, {"a", "b"}));  // two channels in a three-channel group
  const auto g = s.group("g");
  ASSERT_TRUE(g);
  ASSERT_EQ(g->trend.size(), 3u);
  EXPECT_EQ(g->trend[0].index, 0u);
  EXPECT_EQ(g->trend[1].index, 1u);
  EXPECT_EQ(g->trend[2].index, 2u);
  EXPECT_EQ(g->trend[1].values, (std::vector<double>{4, 5, 6}));
  const auto c = s.counters();
  EXPECT_EQ(c.condition_vectors, 7u);
  EXPECT_EQ(c.duplicates, 1u);
  EXPECT_EQ(c.rejected_vectors, 3u);
  const json j = parse(s);
  ASSERT_EQ(j["groups"].size(), 1u);
  EXPECT_EQ(j["groups"][0]["trend"]["index"], json({0, 1, 2}));
  EXPECT_EQ(j["groups"][0]["trend"]["values"][2], json({3.0, 6.0, 9.0}));
  EXPECT_EQ(j["groups"][0]["last"]["index"], 2);
  EXPECT_DOUBLE_EQ(j["groups"][0]["trend"]["time_ms"][1].get<double>(), 600000.0);  // 10 min in ms
}

// Snapshot indices a newer point skipped are gaps in the view, counted (input lost upstream): 2 3 4 8 9 leaves
// 5..7 missing; 6 arriving late fills one; 1 (older than the trend) fills none.
TEST(TwinState, SkippedSnapshotIndicesAreCountedAsMissing) {
  TwinState s;
  for (std::uint64_t i : {2u, 3u, 4u, 8u, 9u}) s.on_condition(vec(i, {1, 2, 3}));
  EXPECT_EQ(s.group("g")->missing, 3u);
  s.on_condition(vec(6, {1, 2, 3}));
  s.on_condition(vec(1, {1, 2, 3}));
  s.on_condition(vec(6, {1, 2, 3}));  // again: a duplicate, nothing filled
  EXPECT_EQ(s.group("g")->missing, 2u);
  EXPECT_EQ(s.counters().snapshots_missing, 2u);
  const json j = parse(s);
  EXPECT_EQ(j["groups"][0]["missing"], 2);
  EXPECT_EQ(j["counters"]["snapshots_missing"], 2);
}

TEST(TwinState, HistoryIsBoundedOldestFirst) {
  StateLimits limits;
  limits.trend_points = 4;
  TwinState s(limits);
  for (std::uint64_t i = 0; i < 10; ++i) s.on_condition(vec(i, {1, 2, 3}));
  const auto g = s.group("g");
  ASSERT_EQ(g->trend.size(), 4u);
  EXPECT_EQ(g->trend.front().index, 6u);
  EXPECT_EQ(g->trend.back().index, 9u);
  EXPECT_EQ(s.counters().trend_points_forgotten, 6u);
}

TEST(TwinState, CausalGraphEdgesFromFactorNamesWithZ) {
  TwinState s;
  // Outcome 1 (channel a): x12 = 0.5 +- 0.1 (z 5), x13 = -0.1 +- 0.2 (z -0.5), xL12 = -0.9 +- 0.3 (z -3),
  // xL11 = 0.8 +- 0.1 (own past), and two unusable ones: a malformed name and a zero std.
  s.on_factors(factors(1, 7, {"x12", "x13", "xL12", "xL11", "y12", "xL13"}, {0.5, -0.1, -0.9, 0.8, 1.0, 0.2},
                       {0.1, 0.2, 0.3, 0.1, 0.1, 0.0}));
  const auto g = s.group("g");
  ASSERT_TRUE(g);
  const auto graph = causal::web::causal_graph(*g);
  EXPECT_EQ(graph.index, 7u);
  EXPECT_EQ(graph.unusable, 2u);
  ASSERT_EQ(graph.edges.size(), 3u);
  EXPECT_EQ(graph.edges[0].from, 2);
  EXPECT_EQ(graph.edges[0].to, 1);
  EXPECT_EQ(graph.edges[0].lag, 0);
  EXPECT_DOUBLE_EQ(graph.edges[0].z, 5.0);
  EXPECT_EQ(graph.edges[1].from, 3);
  EXPECT_DOUBLE_EQ(graph.edges[1].z, -0.5);
  EXPECT_EQ(graph.edges[2].lag, 1);
  EXPECT_DOUBLE_EQ(graph.edges[2].z, -3.0);
  ASSERT_EQ(graph.self_lags.size(), 1u);
  EXPECT_EQ(graph.self_lags[0].from, 1);
  EXPECT_DOUBLE_EQ(graph.self_lags[0].factor, 0.8);
  const json edges = parse(s)["groups"][0]["graph"]["edges"];
  ASSERT_EQ(edges.size(), 3u);
  EXPECT_TRUE(edges[0]["significant"].get<bool>());
  EXPECT_FALSE(edges[1]["significant"].get<bool>());  // |z| 0.5 < 2
  EXPECT_TRUE(edges[2]["significant"].get<bool>());   // |z| 3
}

TEST(TwinState, FactorsOnlyFromTheConditionLevelFilterAndNeverOlder) {
  TwinState s;
  auto sample = factors(1, 3, {"x12"}, {0.5}, {0.1});
  sample.time_scale(causal_twin::SAMPLE_LEVEL);
  s.on_factors(sample);
  auto smoother = factors(1, 3, {"x12"}, {0.5}, {0.1});
  smoother.kind(causal_twin::FIXED_LAG_SMOOTHER);
  s.on_factors(smoother);
  s.on_factors(factors(1, 3, {"x12", "x13"}, {0.5}, {0.1}));  // lengths differ
  EXPECT_EQ(s.counters().factor_messages_skipped, 2u);
  EXPECT_EQ(s.counters().factor_messages_rejected, 1u);
  EXPECT_FALSE(s.group("g"));
  s.on_factors(factors(1, 9, {"x12"}, {0.5}, {0.1}));
  s.on_factors(factors(1, 8, {"x12"}, {-0.5}, {0.1}));  // older, re-sent: the newest stays
  EXPECT_DOUBLE_EQ(s.group("g")->factors.at(1).values[0], 0.5);
  EXPECT_EQ(s.counters().factor_messages, 2u);
}

TEST(TwinState, AlarmBandsFromRaiseToClearAndLateJoiners) {
  TwinState s;
  for (std::uint64_t i = 0; i < 30; ++i) s.on_condition(vec(i, {1, 2, 3}));
  s.on_alarm(alarm("g/1/a/1", causal_twin::RAISED, 10, 10 * 10 * kMinute));
  s.on_alarm(alarm("g/1/a/1", causal_twin::CLEARED, 20, 10 * 10 * kMinute));
  // Joined after the raise: the first event seen is an escalation; the raise is found from its time (snapshot 5).
  s.on_alarm(alarm("g/1/b/2", causal_twin::ESCALATED, 25, 5 * 10 * kMinute + kMinute));
  const auto g = s.group("g");
  const auto& first = g->alarms.at("g/1/a/1");
  EXPECT_EQ(first.raised_index, 10u);
  ASSERT_TRUE(first.cleared_index);
  EXPECT_EQ(*first.cleared_index, 20u);
  EXPECT_FALSE(first.open());
  const auto& second = g->alarms.at("g/1/b/2");
  EXPECT_EQ(second.raised_index, 5u);
  EXPECT_TRUE(second.open());
  const json alarms = parse(s)["groups"][0]["alarms"];
  ASSERT_EQ(alarms.size(), 2u);
  EXPECT_EQ(alarms[0]["cleared_index"], 20);
  EXPECT_TRUE(alarms[1]["cleared_index"].is_null());
  EXPECT_EQ(alarms[1]["severity"], "warning");
  EXPECT_EQ(alarms[1]["root_cause_name"], "b");
}

TEST(TwinState, ClosedAlarmsAreBoundedOpenOnesKept) {
  StateLimits limits;
  limits.closed_alarms = 2;
  TwinState s(limits);
  s.on_alarm(alarm("open", causal_twin::RAISED, 1, 0));
  for (int i = 0; i < 5; ++i) {
    const std::string id = "closed" + std::to_string(i);
    s.on_alarm(alarm(id, causal_twin::RAISED, 2, 0));
    s.on_alarm(alarm(id, causal_twin::CLEARED, 3, 0));
  }
  const auto g = s.group("g");
  ASSERT_EQ(g->alarms.size(), 3u);
  EXPECT_TRUE(g->alarms.count("open"));
  EXPECT_TRUE(g->alarms.count("closed3"));
  EXPECT_TRUE(g->alarms.count("closed4"));
}

TEST(TwinState, RecommendationIsCurrentWhileItsAlarmIsOpen) {
  TwinState s;
  s.on_alarm(alarm("g/1/a/1", causal_twin::RAISED, 10, 0));
  causal_twin::Recommendation r;
  r.recommendation_id("g/1/a/1/1");
  r.alarm_id("g/1/a/1");
  r.asset_group("g");
  r.rank(1);
  r.text("bring b down");
  r.effect_low(std::numeric_limits<double>::quiet_NaN());  // passed through as null, never NaN
  s.on_recommendation(r);
  json rec = parse(s)["groups"][0]["recommendations"][0];
  EXPECT_TRUE(rec["current"].get<bool>());
  EXPECT_EQ(rec["text"], "bring b down");
  EXPECT_TRUE(rec["effect_low"].is_null());
  s.on_alarm(alarm("g/1/a/1", causal_twin::CLEARED, 12, 0));
  rec = parse(s)["groups"][0]["recommendations"][0];
  EXPECT_FALSE(rec["current"].get<bool>());
}

TEST(TwinState, VersionChangesWakeWaiters) {
  TwinState s;
  const auto v0 = s.version();
  EXPECT_FALSE(s.wait_for_change(v0, std::chrono::milliseconds(20)));
  auto later = std::async(std::launch::async, [&] { return s.wait_for_change(v0, std::chrono::seconds(10)); });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  s.on_condition(vec(0, {1, 2, 3}));
  EXPECT_TRUE(later.get());
  EXPECT_EQ(s.version(), v0 + 1);
  EXPECT_EQ(s.json(), s.json());  // one serialisation per version, shared
}

TEST(TwinState, PageViewCarriesOneGroupAndWakesOnlyForIt) {
  TwinState s;
  s.on_condition(vec(0, {1, 2, 3}));
  auto other = vec(0, {4, 5, 6});
  other.asset_group("h");
  s.on_condition(other);
  const auto g0 = s.versions("g"), h0 = s.versions("h");
  other.snapshot_index(1);
  s.on_condition(other);  // a new snapshot of h: g's page does not change
  EXPECT_EQ(s.versions("g"), g0);
  EXPECT_NE(s.versions("h"), h0);
  EXPECT_FALSE(s.wait_for_change("g", g0, std::chrono::milliseconds(20)));
  auto raised = alarm("h/1/a/1", causal_twin::RAISED, 1, 0);
  raised.asset_group("h");
  s.on_alarm(raised);  // an alarm anywhere changes every page's overview
  EXPECT_NE(s.versions("g").overview, g0.overview);
  EXPECT_TRUE(s.wait_for_change("g", g0, std::chrono::milliseconds(20)));

  const json page = json::parse(s.page_json("g"));
  const auto v = s.versions("g");
  EXPECT_EQ(page["version"], std::to_string(v.overview) + "." + std::to_string(v.group));
  EXPECT_EQ(page["group"]["id"], "g");
  EXPECT_EQ(page["group"]["trend"]["index"], json({0}));
  ASSERT_EQ(page["overview"]["groups"].size(), 2u);
  EXPECT_EQ(page["overview"]["groups"][1]["id"], "h");
  EXPECT_EQ(page["overview"]["groups"][1]["open_alarms"], 1);
  EXPECT_EQ(page["overview"]["groups"][1]["worst_severity"], "warning");
  EXPECT_TRUE(page["overview"]["groups"][0]["worst_severity"].is_null());
  EXPECT_TRUE(json::parse(s.page_json("unknown"))["group"].is_null());
}

// The recommender's status line per group reaches the page (group and overview).
TEST(TwinState, AssetStatusIsShownPerGroupAndInTheOverview) {
  TwinState s;
  causal_twin::AssetStatus st;
  st.asset_group("g");
  st.state("learning");
  st.learning_seen(37);
  st.learning_needed(140);
  st.sample_index(36);
  st.text("learning its baseline: 37 of 140 observations, no verdict yet");
  s.on_status(st);
  json page = json::parse(s.page_json("g"));
  EXPECT_EQ(page["group"]["status"]["state"], "learning");
  EXPECT_EQ(page["group"]["status"]["learning_seen"], 37);
  EXPECT_EQ(page["group"]["status"]["learning_needed"], 140);
  EXPECT_EQ(page["overview"]["groups"][0]["state"], "learning");
  const auto before = s.versions("g");
  st.state("stopped");
  st.text("stopped: the machine is not running");
  s.on_status(st);
  EXPECT_NE(s.versions("g").overview, before.overview);  // the state is in the overview
  page = json::parse(s.page_json("g"));
  EXPECT_EQ(page["group"]["status"]["state"], "stopped");
  EXPECT_EQ(s.counters().statuses, 2u);
}

TEST(WhatIfBridge, SendsResendsAndHandsTheMatchingReplyBack) {
  WhatIfBridge bridge;
  causal_twin::WhatIfRequest q;
  q.request_id("q1");
  q.asset_group("g");
  auto asked = std::async(std::launch::async, [&] { return bridge.ask(q, std::chrono::seconds(10)); });
  std::vector<causal_twin::WhatIfRequest> due;
  const auto t0 = WhatIfBridge::Clock::now();
  for (int i = 0; i < 500 && due.empty(); ++i) {
    due = bridge.due(t0);
    if (due.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_EQ(due.size(), 1u);
  EXPECT_EQ(due[0].request_id(), "q1");
  EXPECT_TRUE(bridge.due(t0 + std::chrono::milliseconds(900)).empty());  // not again within a second
  EXPECT_EQ(bridge.due(t0 + std::chrono::milliseconds(1100)).size(), 1u);
  causal_twin::WhatIfReply other;
  other.request_id("someone-else");
  bridge.on_reply(other);
  causal_twin::WhatIfReply mine;
  mine.request_id("q1");
  mine.ok(true);
  mine.text("answer");
  bridge.on_reply(mine);
  const auto out = asked.get();
  EXPECT_EQ(out.status, WhatIfBridge::Status::Answered);
  EXPECT_EQ(out.reply.text(), "answer");
  EXPECT_EQ(bridge.asked(), 1u);
  EXPECT_EQ(bridge.answered(), 1u);
  EXPECT_TRUE(bridge.due(t0 + std::chrono::seconds(5)).empty());  // answered and gone
}

TEST(WhatIfBridge, TimesOutWithoutReplyAndStopsWaiters) {
  WhatIfBridge bridge;
  causal_twin::WhatIfRequest q;
  q.request_id("q1");
  EXPECT_EQ(bridge.ask(q, std::chrono::milliseconds(30)).status, WhatIfBridge::Status::NoReply);
  q.request_id("q2");
  auto asked = std::async(std::launch::async, [&] { return bridge.ask(q, std::chrono::seconds(30)); });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  bridge.stop();
  EXPECT_EQ(asked.get().status, WhatIfBridge::Status::Stopped);
  EXPECT_EQ(bridge.ask(q, std::chrono::seconds(30)).status, WhatIfBridge::Status::Stopped);
}

// The overview is the operator's status line per group (state, worst severity, root cause, action,
// prognosis, learning n of N); a new prognosis line alone is a change every page sees.
TEST(TwinState, OverviewCarriesEveryGroupsStatusLine) {
  TwinState s;
  EXPECT_EQ(s.default_group(), "");
  causal_twin::AssetStatus st;
  st.asset_group("h");
  st.state("alarm");
  st.has_alarm(true);
  st.worst_severity(causal_twin::WARNING);
  st.open_alarms(2);
  st.root_cause_channel(1);
  st.root_cause_name("a");
  st.action("act on a: inspect it");
  st.prognosis_text("a: critical in ~12 h (6-30 h), ~2004-02-19 18:00 UTC");
  st.learning_seen(140);
  st.learning_needed(140);
  s.on_status(st);
  s.on_condition(vec(0, {1, 2, 3}));  // group g has a trend, h has none: a page without ?group= shows g
  EXPECT_EQ(s.default_group(), "g");
  json page = json::parse(s.page_json("g"));
  ASSERT_EQ(page["overview"]["groups"].size(), 2u);
  const json& line = page["overview"]["groups"][1]["status"];
  EXPECT_EQ(page["overview"]["groups"][1]["id"], "h");
  EXPECT_EQ(line["state"], "alarm");
  EXPECT_EQ(line["worst_severity"], "warning");
  EXPECT_EQ(line["open_alarms"], 2);
  EXPECT_EQ(line["root_cause_channel"], 1);
  EXPECT_EQ(line["root_cause_name"], "a");
  EXPECT_EQ(line["action"], "act on a: inspect it");
  EXPECT_EQ(line["prognosis_text"], "a: critical in ~12 h (6-30 h), ~2004-02-19 18:00 UTC");
  EXPECT_EQ(line["learning_seen"], 140);
  EXPECT_TRUE(page["overview"]["groups"][0]["status"].is_null());
  EXPECT_EQ(page["overview"]["groups"][0]["last_time_ms"], 0.0);
  const auto before = s.versions("g");
  st.prognosis_text("a: critical in ~11 h (5-28 h), ~2004-02-19 17:00 UTC");
  s.on_status(st);
  EXPECT_NE(s.versions("g").overview, before.overview);
}

static causal_twin::Prognosis prognosis(const std::string& alarm_id, const std::string& level, std::uint64_t index, double hours) {
  causal_twin::Prognosis p;
  p.asset_group("g");
  p.channel(1);
  p.channel_name("a");
  p.level(level);
  p.alarm_id(alarm_id);
  p.sample_index(index);
  p.time_ns(static_cast<std::int64_t>(index) * 10 * kMinute);
  p.known(std::isfinite(hours));
  p.hours(hours);
  p.hours_low(hours / 2);
  p.hours_high(std::numeric_limits<double>::quiet_NaN());
  p.eta_time_ns(std::isfinite(hours) ? p.time_ns() + static_cast<std::int64_t>(hours * 60) * kMinute : 0);
  return p;
}

// The prognosis of a channel is shown while its alarm is open, newest first; NaN reaches the page as null; the
// time scale of every alarm is named (the sample-level engine's ids are "<group>/sample/...").
TEST(TwinState, PrognosisWhileItsAlarmIsOpenAndTimeScalePerAlarm) {
  TwinState s;
  s.on_condition(vec(0, {1, 2, 3}));
  s.on_alarm(alarm("g/1/feature_drift/1", causal_twin::RAISED, 5, 50 * kMinute));
  auto sample = alarm("g/sample/1/innovation_nis/1", causal_twin::RAISED, 7, 70 * kMinute);
  s.on_alarm(sample);
  auto health = alarm("g/health/estimator", causal_twin::RAISED, 7, 70 * kMinute);
  health.category("health");
  s.on_alarm(health);
  s.on_prognosis(prognosis("g/1/feature_drift/1", "critical", 9, 12.0));
  s.on_prognosis(prognosis("g/1/feature_drift/1", "critical", 8, 20.0));  // older: not kept
  s.on_prognosis(prognosis("g/1/feature_drift/1", "end_of_life", 9, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_EQ(s.counters().prognoses, 3u);
  EXPECT_EQ(s.counters().prognoses_stale, 1u);
  json g = json::parse(s.page_json("g"))["group"];
  std::map<std::string, std::string> scales;
  for (const auto& a : g["alarms"]) scales[a["id"].get<std::string>()] = a["time_scale"].get<std::string>();
  EXPECT_EQ(scales["g/1/feature_drift/1"], "condition");
  EXPECT_EQ(scales["g/sample/1/innovation_nis/1"], "sample");
  EXPECT_EQ(scales["g/health/estimator"], "twin");
  ASSERT_EQ(g["prognoses"].size(), 2u);
  EXPECT_EQ(g["prognoses"][0]["level"], "critical");
  EXPECT_EQ(g["prognoses"][0]["hours"], 12.0);
  EXPECT_EQ(g["prognoses"][0]["eta_ms"], (90.0 + 720.0) * 60e3);
  EXPECT_TRUE(g["prognoses"][0]["hours_high"].is_null());
  EXPECT_EQ(g["prognoses"][1]["level"], "end_of_life");
  EXPECT_TRUE(g["prognoses"][1]["hours"].is_null());
  EXPECT_TRUE(g["prognoses"][1]["eta_ms"].is_null());
  s.on_alarm(alarm("g/1/feature_drift/1", causal_twin::CLEARED, 12, 50 * kMinute));
  g = json::parse(s.page_json("g"))["group"];
  EXPECT_EQ(g["prognoses"].size(), 0u) << "a cleared alarm's forecast is history";
}
