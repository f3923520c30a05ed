// twin-web's approve button without DDS or HTTP: the page's request checked (the authenticated user wins), the
// intervention planned from the state twin-web holds (the same one causal-approve makes: fields and request id),
// the start taken from the plant's clock, else the estimator's trend, else the recommendation's index; unknown
// recommendations, non-levers, a second approval and an overlapping change refused; the bridge hands the DDS
// thread's answer back.
#include "approval_request.hpp"
#include "twin_state.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <future>
#include <thread>

using causal::web::ApprovalAsk;
using causal::web::ApprovalBridge;
using causal::web::ApprovalResult;
using causal::web::SourceClock;
using causal::web::TwinState;
using nlohmann::json;

namespace {

constexpr std::int64_t kNow = 1'800'000'000'000'000'000;

causal_twin::Recommendation lever(const std::string& id, bool reliable = true) {
  causal_twin::Recommendation r;
  r.recommendation_id(id);
  r.asset_group("g");
  r.rank(1);
  r.action_kind("upstream_lever");
  r.reliable(reliable);
  r.intervene_channel(2);
  r.target_channel(1);
  r.delta(std::log(0.8));
  r.horizon_snapshots(12);
  r.sample_index(100);
  return r;
}

ApprovalAsk ask(const std::string& rec) {
  ApprovalAsk a;
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}, {"recommendation_id", rec}}, "ann", a), "");
  return a;
}

}  // namespace

TEST(ApprovalRequest, TheAuthenticatedUserApprovesAndBadBodiesAreRefused) {
  ApprovalAsk a;
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}, {"recommendation_id", "r"}, {"user", "mallory"}},
                                        "ann", a), "");
  EXPECT_EQ(a.act.user, "ann");
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}, {"recommendation_id", "r"}, {"user", "bob"}}, "", a),
            "");
  EXPECT_EQ(a.act.user, "bob");  // no authentication: the body's user
  EXPECT_FALSE(a.act.duration.has_value());
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}, {"recommendation_id", "r"}}, "", a),
            "user (string) is required");
  EXPECT_EQ(causal::web::parse_approval(json{{"recommendation_id", "r"}}, "ann", a), "asset_group (string) is required");
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}}, "ann", a), "recommendation_id (string) is required");
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}, {"recommendation_id", "r"}, {"duration_snapshots", 0}},
                                        "ann", a), "duration_snapshots must be an integer in 1..1000000");
  EXPECT_EQ(causal::web::parse_approval(json{{"asset_group", "g"}, {"recommendation_id", "r"}, {"duration_snapshots", 30}},
                                        "ann", a), "");
  EXPECT_EQ(a.act.duration, 30u);
  EXPECT_EQ(causal::web::parse_approval(json::array(), "ann", a), "the body must be a JSON object");
}

TEST(ApprovalRequest, PlannedAsCausalApproveWouldFromThePlantsClock) {
  TwinState state;
  state.on_recommendation(lever("g/1/1"));
  SourceClock clock;
  clock.on_input("g", 200, 2'000'000'000);
  clock.on_input("g", 201, 2'600'000'000);  // 0.6 s cadence
  clock.on_input("g", 150, 1);              // older: the clock does not go back
  const auto plan = causal::web::plan_approval(ask("g/1/1"), state.group("g"), clock.latest("g"), 3, kNow);
  ASSERT_EQ(plan.status, 200) << plan.why;
  const auto& iv = plan.intervention;
  EXPECT_EQ(iv.request_id(), "g/g/1/1@204/ann");
  EXPECT_EQ(iv.start_snapshot_index(), 204u);
  EXPECT_EQ(iv.start_time_ns(), 2'600'000'000 + 3 * 600'000'000);
  EXPECT_EQ(iv.duration_snapshots(), 12u);
  EXPECT_EQ(iv.channel(), 2);
  EXPECT_EQ(iv.target_channel(), 1);
  EXPECT_NEAR(iv.change_percent(), -20.0, 1e-9);
  EXPECT_EQ(iv.approved_by(), "ann");
  EXPECT_EQ(iv.approved_time_ns(), kNow);
  EXPECT_EQ(iv.recommendation_id(), "g/1/1");
  // Without the plant's clock: the recommendation's own index (no trend either), time unknown.
  const auto fallback = causal::web::plan_approval(ask("g/1/1"), state.group("g"), std::nullopt, 3, kNow);
  ASSERT_EQ(fallback.status, 200) << fallback.why;
  EXPECT_EQ(fallback.intervention.start_snapshot_index(), 103u);
  EXPECT_EQ(fallback.intervention.start_time_ns(), 0);
}

TEST(ApprovalRequest, UnknownNotALeverAlreadyApprovedAndOverlappingAreRefused) {
  TwinState state;
  state.on_recommendation(lever("g/1/1"));
  state.on_recommendation(lever("g/1/2"));
  state.on_recommendation(lever("g/1/3", false));
  EXPECT_EQ(causal::web::plan_approval(ask("g/9/9"), state.group("g"), std::nullopt, 3, kNow).status, 404);
  EXPECT_EQ(causal::web::plan_approval(ask("g/1/1"), state.group("other"), std::nullopt, 3, kNow).status, 404);
  const auto not_lever = causal::web::plan_approval(ask("g/1/3"), state.group("g"), std::nullopt, 3, kNow);
  EXPECT_EQ(not_lever.status, 409);
  EXPECT_NE(not_lever.why.find("claims no reliable lever"), std::string::npos) << not_lever.why;

  auto first = causal::web::plan_approval(ask("g/1/1"), state.group("g"), std::nullopt, 3, kNow);
  ASSERT_EQ(first.status, 200);
  state.on_intervention(first.intervention);  // come back from the bus: snapshots 103..114 on channel 2
  const auto again = causal::web::plan_approval(ask("g/1/1"), state.group("g"), std::nullopt, 3, kNow);
  EXPECT_EQ(again.status, 409);
  EXPECT_EQ(again.already, "g/g/1/1@103/ann");
  const auto overlap = causal::web::plan_approval(ask("g/1/2"), state.group("g"), std::nullopt, 3, kNow);
  EXPECT_EQ(overlap.status, 409);
  EXPECT_EQ(overlap.why, "the change would overlap approval g/g/1/1@103/ann on the same channel (snapshots 103..114)");
  SourceClock later;
  later.on_input("g", 112, 0);  // starts at 115: after the first window
  EXPECT_EQ(causal::web::plan_approval(ask("g/1/2"), state.group("g"), later.latest("g"), 3, kNow).status, 200);
}

TEST(ApprovalRequest, TheBridgeHandsTheWritersAnswerBack) {
  ApprovalBridge bridge;
  causal_twin::Intervention iv;
  iv.request_id("g/r@1/ann");
  auto asked = std::async(std::launch::async, [&] { return bridge.ask(iv, std::chrono::seconds(10)); });
  std::vector<causal_twin::Intervention> due;
  for (int i = 0; i < 500 && due.empty(); ++i) {
    due = bridge.due(ApprovalBridge::Clock::now());
    if (due.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(due.size(), 1u);
  ApprovalResult other;
  other.id = "someone/else";
  bridge.on_reply(other);  // not asked for: ignored
  ApprovalResult r;
  r.id = "g/r@1/ann";
  r.published = true;
  r.readers = 3;
  bridge.on_reply(r);
  const auto out = asked.get();
  EXPECT_EQ(out.status, ApprovalBridge::Status::Answered);
  EXPECT_TRUE(out.reply.published);
  EXPECT_EQ(out.reply.readers, 3u);
  EXPECT_EQ(bridge.asked(), 1u);
  EXPECT_EQ(bridge.answered(), 1u);
  const json j = causal::web::approval_json(iv, out.reply);
  EXPECT_EQ(j["request_id"], "g/r@1/ann");
  EXPECT_EQ(j["published"], true);
}
