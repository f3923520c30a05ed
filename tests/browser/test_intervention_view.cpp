// twin-web's view of the closed loop without DDS: an approved intervention (causal_twin/intervention) and the
// twin's check of it (causal_twin/intervention_outcome) joined by request id in the group's JSON (what /api/state
// and the page's events carry), in either order of arrival, once per request id, bounded, with non-finite
// numbers as null and the channel names of the group; and what a restarted twin-web reads back from the
// historian's tables (--db).
#include "history_interventions.hpp"
#include "twin_state.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <unistd.h>

using causal::web::StateLimits;
using causal::web::TwinState;
using nlohmann::json;

namespace {

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000;  // 1.7e12 ms
constexpr std::int64_t kApprovedNs = 1'700'000'600'000'000'000;

causal_twin::ConditionVector vec() {
  causal_twin::ConditionVector v;
  v.asset_group("g");
  v.feature("level");
  v.snapshot_index(0);
  v.time_ns(kStartNs);
  v.channel_names({"inlet", "bearing", "pump"});
  v.values({1.0, 2.0, 3.0});
  return v;
}

causal_twin::Intervention approval(const std::string& id, std::uint64_t start = 250) {
  causal_twin::Intervention i;
  i.request_id(id);
  i.asset_group("g");
  i.channel(3);
  i.change_percent(-25.5);
  i.start_snapshot_index(start);
  i.start_time_ns(kStartNs);
  i.duration_snapshots(24);
  i.recommendation_id("g/rec-7");
  i.target_channel(2);
  i.approved_by("ann");
  i.approved_time_ns(kApprovedNs);
  return i;
}

causal_twin::InterventionOutcome outcome(const std::string& id) {
  causal_twin::InterventionOutcome o;
  o.request_id(id);
  o.asset_group("g");
  o.recommendation_id("g/rec-7");
  o.channel(3);
  o.target_channel(2);
  o.start_snapshot_index(250);
  o.end_snapshot_index(273);
  o.status("checked");
  o.predicted_percent(-12.5);
  o.predicted_percent_low(-20.0);
  o.predicted_percent_high(-5.0);
  o.confidence(0.9);
  o.observed_percent(-10.25);
  o.inside(true);
  o.improved(true);
  o.lever_trust(0.75);
  o.lever_claimed(true);
  o.text("observed -10.2 % inside the predicted -20.0 % to -5.0 %");
  return o;
}

const json kApproval = {{"channel", 3},
                        {"channel_name", "pump"},
                        {"change_percent", -25.5},
                        {"start_index", 250},
                        {"end_index", 273},
                        {"duration", 24},
                        {"start_time_ms", 1.7e12},
                        {"recommendation_id", "g/rec-7"},
                        {"target_channel", 2},
                        {"target_name", "bearing"},
                        {"approved_by", "ann"},
                        {"approved_time_ms", 1.7000006e12}};

const json kOutcome = {{"status", "checked"},
                       {"start_index", 250},
                       {"end_index", 273},
                       {"predicted_percent", -12.5},
                       {"predicted_percent_low", -20.0},
                       {"predicted_percent_high", -5.0},
                       {"confidence", 0.9},
                       {"observed_percent", -10.25},
                       {"inside", true},
                       {"improved", true},
                       {"lever_trust", 0.75},
                       {"lever_claimed", true},
                       {"text", "observed -10.2 % inside the predicted -20.0 % to -5.0 %"}};

json expected(const std::string& id, std::uint64_t arrival, const json& outcome_part) {
  json e = kApproval;
  e["request_id"] = id;
  e["arrival"] = arrival;
  e["outcome"] = outcome_part;
  return e;
}

json interventions_of(const TwinState& s) { return json::parse(s.page_json("g"))["group"]["interventions"]; }

}  // namespace

TEST(InterventionView, AnApprovalIsShownThenJoinedByItsOutcome) {
  TwinState s;
  s.on_condition(vec());
  const auto before = s.versions("g");
  s.on_intervention(approval("g/rec-7@250/ann"));
  EXPECT_NE(s.versions("g"), before) << "a page waiting for the group must see the approval";
  EXPECT_EQ(interventions_of(s), json::array({expected("g/rec-7@250/ann", 1, nullptr)}));

  s.on_intervention_outcome(outcome("g/rec-7@250/ann"));
  EXPECT_EQ(interventions_of(s), json::array({expected("g/rec-7@250/ann", 2, kOutcome)}));
  // /api/state carries the same entry and the counts.
  const json state = json::parse(*s.json());
  EXPECT_EQ(state["groups"][0]["interventions"], interventions_of(s));
  EXPECT_EQ(state["counters"]["interventions"], 1);
  EXPECT_EQ(state["counters"]["intervention_outcomes"], 1);
  EXPECT_EQ(state["counters"]["interventions_forgotten"], 0);
}

TEST(InterventionView, AnOutcomeBeforeItsApprovalAndARedeliveryAreOneEntry) {
  TwinState s;
  s.on_condition(vec());
  s.on_intervention_outcome(outcome("r1"));
  // Only the outcome: what it says itself; the approval's own fields are null.
  json alone = interventions_of(s);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_EQ(alone[0]["approved_by"], nullptr);
  EXPECT_EQ(alone[0]["start_index"], nullptr);
  EXPECT_EQ(alone[0]["channel_name"], "pump");
  EXPECT_EQ(alone[0]["target_name"], "bearing");
  EXPECT_EQ(alone[0]["outcome"], kOutcome);

  s.on_intervention(approval("r1"));
  s.on_intervention(approval("r1"));  // a transient-local replay of the same approval
  EXPECT_EQ(interventions_of(s), json::array({expected("r1", 3, kOutcome)}));
  EXPECT_EQ(s.counters().interventions, 2u);
  EXPECT_EQ(s.counters().intervention_outcomes, 1u);
}

TEST(InterventionView, KeepsTheNewestPerGroupAndCountsTheForgotten) {
  StateLimits limits;
  limits.interventions = 2;
  TwinState s(limits);
  s.on_intervention(approval("a", 100));
  s.on_intervention(approval("b", 200));
  s.on_intervention_outcome(outcome("a"));  // "a" is now the newest arrival: "b" goes first
  s.on_intervention(approval("c", 300));
  const json list = interventions_of(s);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0]["request_id"], "a");
  EXPECT_EQ(list[1]["request_id"], "c");
  EXPECT_EQ(list[1]["outcome"], nullptr);
  EXPECT_EQ(s.counters().interventions_forgotten, 1u);
  // Without condition vectors the names are unknown (""), the channels still there.
  EXPECT_EQ(list[1]["channel_name"], "");
  EXPECT_EQ(list[1]["channel"], 3);
}

TEST(InterventionView, NonFiniteNumbersAreNull) {
  TwinState s;
  auto o = outcome("x");
  o.status("no_data");
  o.observed_percent(NAN);
  o.lever_trust(INFINITY);
  s.on_intervention(approval("x"));
  s.on_intervention_outcome(o);
  const json got = interventions_of(s)[0]["outcome"];
  EXPECT_EQ(got["status"], "no_data");
  EXPECT_EQ(got["observed_percent"], nullptr);
  EXPECT_EQ(got["lever_trust"], nullptr);
  EXPECT_EQ(got["predicted_percent"], -12.5);
}

// The historian's rows (as causal-recorder writes them: the CSV cells) read back by a restarted twin-web give the
// same entry as the live messages did; a row that does not convert is counted, not shown.
TEST(InterventionView, ARestartedTwinWebShowsTheStoredApprovalsAndOutcomes) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("causal-iv-history-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    auto store = causal::history::open_history("sqlite:" + (dir / "history.db").string());
    store->add("interventions", {"r1", "g", "3", "-25.5", "250", "1700000000000000000", "2023-11-14 22:13:20", "24",
                                 "g/rec-7", "2", "ann", "1700000600000000000", "2023-11-14 22:23:20"});
    store->add("intervention_outcomes", {"r1", "g", "g/rec-7", "3", "2", "250", "273", "checked", "-12.5", "-20", "-5",
                                         "0.9", "-10.25", "true", "true", "0.75", "true",
                                         "observed -10.2 % inside the predicted -20.0 % to -5.0 %"});
    store->add("intervention_outcomes", {"r2", "g", "g/rec-8", "3", "2", "300", "", "checked", "1", "1", "1", "0.9",
                                         "1", "true", "true", "0.5", "true", "end snapshot missing: unreadable"});
    ASSERT_EQ(store->commit(), 3u);
    TwinState s;
    s.on_condition(vec());
    const auto load = causal::web::load_interventions(*store, s);
    EXPECT_EQ(load.approvals, 1u);
    EXPECT_EQ(load.outcomes, 1u);
    EXPECT_EQ(load.unreadable, 1u);
    EXPECT_EQ(interventions_of(s), json::array({expected("r1", 2, kOutcome)}));
  }
  fs::remove_all(dir);
}
