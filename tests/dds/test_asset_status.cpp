// The operator's status line per asset group (alarm-recommender's AssetStatusBoard,
// fed by a real AlarmEngine on synthetic data with a known change) and alarm ids that differ across time scales.
#include "asset_status.hpp"


#include "../alarms/synthetic_group.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace {

using causal::alarms::AlarmEngine;
using causal::alarms::AlarmParams;
using causal::recommender::AssetStatusBoard;
using causal::recommender::StatusInput;
namespace syn = causal::alarms::test;

struct Step {
  causal_twin::AssetStatus status;
  bool published = false;
};

// Feeds the observations; returns the status after each one.
std::vector<Step> run(AlarmEngine& engine, AssetStatusBoard& board, const std::vector<causal::alarms::Observation>& obs) {
  std::vector<Step> steps;
  for (const auto& o : obs) {
    const auto before = engine.not_running_observations();
    engine.observe(o);
    StatusInput in;
    in.condition = &engine;
    in.stopped_now = engine.not_running_observations() > before;
    in.index = o.index;
    in.time_ns = o.time_ns;
    Step s;
    s.published = board.update("g", in, s.status);
    if (!s.published && !steps.empty()) s.status = steps.back().status;  // the line as a reader has it
    steps.push_back(s);
  }
  return steps;
}

// 400 observations of the synthetic group; bearing 2's own change from 250 on, still rising (a settled step
// would be an operating change, re-baselined).
std::vector<causal::alarms::Observation> rising_bearing2() {
  syn::SyntheticConfig cfg;
  cfg.n = 400;
  cfg.own_change = [](int t) { return t >= 250 ? 0.3 * (t - 250) : 0.0; };
  return syn::make_run(cfg);
}

}  // namespace

TEST(AssetStatus, NeverHealthyWhileLearningThenHealthyThenAlarmWithRootCause) {
  const auto obs = rising_bearing2();
  AlarmEngine engine("g", syn::channel_names4(), {}, AlarmParams{});
  AssetStatusBoard board;
  const auto steps = run(engine, board, obs);
  const std::uint32_t needed = 20 + 120;
  std::string state = "";
  std::map<std::string, int> first;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (steps[i].published) state = steps[i].status.state();
    if (!first.count(state)) first[state] = static_cast<int>(i);
    if (i + 1 < needed) {
      ASSERT_EQ(state, "learning") << "observation " << i;
      EXPECT_EQ(steps[i].status.learning_seen(), i + 1);  // n of N, published at every observation
      EXPECT_EQ(steps[i].status.learning_needed(), needed);
    }
  }
  ASSERT_TRUE(first.count("healthy") && first.count("alarm"));
  std::cout << "learning from 0, healthy from " << first["healthy"] << ", alarm from " << first["alarm"] << "\n";
  EXPECT_EQ(first["learning"], 0);
  EXPECT_GE(first["healthy"], static_cast<int>(needed) - 1);
  EXPECT_LT(first["healthy"], 250);
  EXPECT_GE(first["alarm"], 250);
  const auto& last = steps[static_cast<std::size_t>(first["alarm"])].status;
  EXPECT_TRUE(last.has_alarm());
  EXPECT_EQ(last.root_cause_channel(), 2);
  EXPECT_EQ(last.root_cause_name(), "bearing 2");
  EXPECT_NE(last.text().find("root cause bearing 2"), std::string::npos) << last.text();
  // Published on change only: far fewer messages than observations once learned.
  EXPECT_LT(board.published(), needed + 20);
}

TEST(AssetStatus, AMachineBelowItsOperatingGateIsStoppedNotHealthyNorAFault) {
  syn::SyntheticConfig cfg;
  cfg.n = 220;
  auto obs = syn::make_run(cfg);
  for (std::size_t i = 200; i < obs.size(); ++i) obs[i].features *= 0.01;  // every channel at 1 %: not running
  AlarmEngine engine("g", syn::channel_names4(), {}, AlarmParams{});
  AssetStatusBoard board;
  const auto steps = run(engine, board, obs);
  EXPECT_EQ(steps[199].status.state(), "healthy");
  ASSERT_TRUE(steps[200].published);
  EXPECT_EQ(steps[200].status.state(), "stopped") << steps[200].status.text();
  EXPECT_FALSE(steps[200].status.has_alarm());
  for (std::size_t i = 201; i < steps.size(); ++i) EXPECT_FALSE(steps[i].published) << i;  // no change, no message
}

TEST(AlarmIds, ScopedEnginesNeverShareAnIdWithTheConditionLevel) {
  const auto obs = rising_bearing2();
  AlarmEngine condition("g", syn::channel_names4(), {}, AlarmParams{});
  AlarmEngine sample("g", syn::channel_names4(), {}, AlarmParams{});
  sample.set_id_scope("sample");
  std::set<std::string> condition_ids, sample_ids;
  for (const auto& o : obs) {
    for (const auto& e : condition.observe(o)) condition_ids.insert(e.alarm_id);
    for (const auto& e : sample.observe(o)) sample_ids.insert(e.alarm_id);
  }
  ASSERT_FALSE(condition_ids.empty());
  ASSERT_EQ(sample_ids.size(), condition_ids.size());  // the same data raises the same alarms ...
  for (const auto& id : condition_ids) {
    EXPECT_EQ(sample_ids.count(id), 0u) << id;  // ... under other ids
    EXPECT_EQ(id.find("/sample/"), std::string::npos) << id;  // condition level unchanged: <group>/<ch>/<kind>/<n>
  }
  for (const auto& id : sample_ids) EXPECT_EQ(id.rfind("g/sample/", 0), 0u) << id;
  EXPECT_TRUE(condition_ids.count("g/2/feature_drift/1")) << "the changed channel's alarm";
}

// The status line carries the prognosis of its worst alarm (the node's function), only in alarm.
TEST(AssetStatus, CarriesThePrognosisLineOnlyWhileInAlarm) {
  const auto obs = rising_bearing2();
  AlarmEngine engine("g", syn::channel_names4(), {}, AlarmParams{});
  AssetStatusBoard board;
  int asked = 0;
  std::string asked_for;
  bool seen_alarm = false;
  for (const auto& o : obs) {
    engine.observe(o);
    StatusInput in;
    in.condition = &engine;
    in.index = o.index;
    in.time_ns = o.time_ns;
    in.prognosis = [&](const causal::alarms::AlarmEvent& worst) {
      ++asked;
      asked_for = worst.alarm_id;
      return "prognosis of " + worst.alarm_id;
    };
    causal_twin::AssetStatus s;
    if (!board.update("g", in, s)) continue;
    if (s.state() == "alarm") {
      seen_alarm = true;
      EXPECT_EQ(s.prognosis_text(), "prognosis of " + asked_for) << s.text();
    } else {
      EXPECT_EQ(s.prognosis_text(), "") << s.state();
    }
  }
  EXPECT_TRUE(seen_alarm);
  EXPECT_GT(asked, 0);
}
