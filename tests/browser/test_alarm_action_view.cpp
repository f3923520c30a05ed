// twin-web's side of alarm management without DDS: the page's action checked into an AlarmAction (the user from
// authentication wins), applied results shown per alarm (acknowledged by, shelved until, per source), and the
// bridge handing the matching result back.
#include "alarm_action_bridge.hpp"
#include "alarm_action_request.hpp"
#include "twin_state.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <future>
#include <thread>

using causal::web::AlarmActionBridge;
using causal::web::parse_alarm_action;
using causal::web::TwinState;
using nlohmann::json;

namespace {

constexpr std::int64_t kNow = 1'800'000'000'000'000'000;

causal_twin::Alarm alarm(const std::string& id) {
  causal_twin::Alarm a;
  a.alarm_id(id);
  a.asset_group("g");
  a.channel(1);
  a.state(causal_twin::RAISED);
  a.severity(causal_twin::WARNING);
  a.raised_time_ns(1);
  return a;
}

causal_twin::AlarmActionResult result(const std::string& rid, const std::string& id, causal_twin::AlarmActionKind k,
                                      bool applied, std::int64_t until = 0) {
  causal_twin::AlarmActionResult r;
  r.request_id(rid);
  r.asset_group("g");
  r.alarm_id(id);
  r.action(k);
  r.user_name("ann");
  r.reason(k == causal_twin::SHELVE ? "cable" : "");
  r.until_ns(until);
  r.applied(applied);
  return r;
}

}  // namespace

TEST(AlarmActionRequest, ChecksTheBodyAndTakesTheAuthenticatedUser) {
  causal_twin::AlarmAction a;
  EXPECT_EQ(parse_alarm_action(json{{"asset_group", "g"}, {"alarm_id", "g/1/x/0"}, {"action", "acknowledge"},
                                    {"user", "ann"}}, "", kNow, a), "");
  EXPECT_EQ(a.action(), causal_twin::ACKNOWLEDGE);
  EXPECT_EQ(a.user_name(), "ann");
  EXPECT_EQ(a.time_ns(), kNow);
  EXPECT_EQ(a.until_ns(), 0);
  // With basic authentication the body cannot act in another's name.
  EXPECT_EQ(parse_alarm_action(json{{"asset_group", "g"}, {"alarm_id", "g/1/x/0"}, {"action", "acknowledge"},
                                    {"user", "mallory"}}, "ops", kNow, a), "");
  EXPECT_EQ(a.user_name(), "ops");
  EXPECT_EQ(parse_alarm_action(json{{"asset_group", "g"}, {"alarm_id", "g/1/x/0"}, {"action", "shelve"},
                                    {"minutes", 1.5}, {"reason", "cable"}, {"user", "ann"}}, "", kNow, a), "");
  EXPECT_EQ(a.action(), causal_twin::SHELVE);
  EXPECT_EQ(a.until_ns(), kNow + 90'000'000'000);
  EXPECT_EQ(a.reason(), "cable");
  // Refused, each with its reason.
  const json base{{"asset_group", "g"}, {"alarm_id", "g/1/x/0"}, {"user", "ann"}};
  auto with = [&](json extra) {
    json b = base;
    b.update(extra);
    return b;
  };
  EXPECT_EQ(parse_alarm_action(json::array(), "", kNow, a), "the body must be a JSON object");
  EXPECT_EQ(parse_alarm_action(with({{"action", "delete"}}), "", kNow, a), "action must be acknowledge, shelve or unshelve");
  EXPECT_EQ(parse_alarm_action(with({{"action", "shelve"}, {"reason", "x"}}), "", kNow, a),
            "minutes (number) is required to shelve");
  EXPECT_EQ(parse_alarm_action(with({{"action", "shelve"}, {"minutes", 0}, {"reason", "x"}}), "", kNow, a),
            "minutes must be > 0 and at most 10080 (a week)");
  EXPECT_EQ(parse_alarm_action(with({{"action", "shelve"}, {"minutes", 10081}, {"reason", "x"}}), "", kNow, a),
            "minutes must be > 0 and at most 10080 (a week)");
  EXPECT_EQ(parse_alarm_action(with({{"action", "shelve"}, {"minutes", 5}}), "", kNow, a), "a reason is required to shelve");
  EXPECT_EQ(parse_alarm_action(json{{"asset_group", "g"}, {"alarm_id", "g/1/x/0"}, {"action", "acknowledge"}}, "",
                               kNow, a), "user (string) is required");
  EXPECT_EQ(parse_alarm_action(with({{"action", "acknowledge"}, {"reason", std::string(256, 'r')}}), "", kNow, a),
            "reason must be a string of at most 255 bytes");
  EXPECT_EQ(parse_alarm_action(with({{"action", "acknowledge"}, {"alarm_id", 5}}), "", kNow, a),
            "alarm_id (string) is required");
}

TEST(AlarmActionView, AppliedResultsMarkTheAlarmAndItsSource) {
  TwinState s;
  s.on_alarm(alarm("g/1/feature_drift/0"));
  s.on_alarm(alarm("g/1/feature_drift/1"));  // the same source raised again
  s.on_alarm(alarm("g/2/feature_drift/0"));
  s.on_action_result(result("r1", "g/2/feature_drift/0", causal_twin::ACKNOWLEDGE, true));
  s.on_action_result(result("r2", "g/1/feature_drift/0", causal_twin::SHELVE, true, kNow));
  s.on_action_result(result("r3", "g/2/feature_drift/0", causal_twin::SHELVE, false, kNow));  // refused: no change
  auto g = s.group("g");
  EXPECT_TRUE(g->alarms.at("g/2/feature_drift/0").acknowledged);
  EXPECT_EQ(g->alarms.at("g/2/feature_drift/0").acknowledged_by, "ann");
  EXPECT_FALSE(g->alarms.at("g/2/feature_drift/0").shelved);
  EXPECT_TRUE(g->alarms.at("g/1/feature_drift/0").shelved);
  EXPECT_TRUE(g->alarms.at("g/1/feature_drift/1").shelved);
  EXPECT_EQ(g->alarms.at("g/1/feature_drift/1").shelved_until_ns, kNow);
  EXPECT_EQ(g->alarms.at("g/1/feature_drift/1").shelve_reason, "cable");
  EXPECT_EQ(s.counters().alarm_actions, 2u);
  EXPECT_EQ(s.counters().alarm_actions_refused, 1u);
  const json alarms = json::parse(*s.json())["groups"][0]["alarms"];
  ASSERT_EQ(alarms.size(), 3u);
  for (const auto& a : alarms) {
    if (a["id"] == "g/2/feature_drift/0") {
      EXPECT_EQ(a["acknowledged"], true);
      EXPECT_EQ(a["acknowledged_by"], "ann");
      EXPECT_EQ(a["shelved"], false);
    } else {
      EXPECT_EQ(a["shelved"], true);
      EXPECT_EQ(a["shelved_until_ms"], kNow / 1'000'000);
    }
  }
  // The expiry lifts the whole source; an escalation of an acknowledged alarm (flag FALSE) needs a new one.
  s.on_action_result(result("expired/g/1/feature_drift/0/1", "g/1/feature_drift/0", causal_twin::UNSHELVE, true));
  auto esc = alarm("g/2/feature_drift/0");
  esc.state(causal_twin::ESCALATED);
  s.on_alarm(esc);
  g = s.group("g");
  EXPECT_FALSE(g->alarms.at("g/1/feature_drift/1").shelved);
  EXPECT_FALSE(g->alarms.at("g/2/feature_drift/0").acknowledged);
  EXPECT_EQ(g->alarms.at("g/2/feature_drift/0").acknowledged_by, "");
}

TEST(AlarmActionBridge, SendsResendsAndHandsTheMatchingResultBack) {
  AlarmActionBridge b;
  causal_twin::AlarmAction a;
  a.request_id("q1");
  auto waiting = std::async(std::launch::async, [&] { return b.ask(a, std::chrono::seconds(10)); });
  std::vector<causal_twin::AlarmAction> due;
  while (due.empty()) {
    due = b.due(AlarmActionBridge::Clock::now());
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(due.size(), 1u);
  EXPECT_TRUE(b.due(AlarmActionBridge::Clock::now()).empty());  // not again within a second
  EXPECT_EQ(b.due(AlarmActionBridge::Clock::now() + std::chrono::seconds(2)).size(), 1u);  // resent after it
  b.on_reply(result("other", "g/1/x/0", causal_twin::ACKNOWLEDGE, true));  // another sender's: ignored
  b.on_reply(result("q1", "g/1/x/0", causal_twin::ACKNOWLEDGE, false));
  const auto out = waiting.get();
  EXPECT_EQ(out.status, AlarmActionBridge::Status::Answered);
  EXPECT_FALSE(out.reply.applied());
  EXPECT_EQ(b.asked(), 1u);
  EXPECT_EQ(b.answered(), 1u);
  b.stop();
  EXPECT_EQ(b.ask(a, std::chrono::seconds(1)).status, AlarmActionBridge::Status::Stopped);
}
