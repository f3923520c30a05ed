// causal::advice::AlarmDesk (common/advice/src/alarm_desk.cpp): the whole judging chain of one observation,
// driven with plain inputs (no DDS). The truth is independent of the desk: the injected change (channel 2's own
// noise ramps up from observation 400), an engine fed the same stream directly, and a desk that never stopped.
#include "causal/advice/alarm_desk.hpp"

#include "../alarms/synthetic_group.hpp"
#include "causal/estimation/state_archive.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace causal::advice {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path;
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() / ("alarm_desk_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

const std::string kGroup = "ims2";
constexpr int kChange = 400;  // channel 2 (index 1) degrades from here on

std::vector<JudgedInput> degrading_stream() {
  alarms::test::SyntheticConfig cfg;
  cfg.seed = 7;
  cfg.with_factors = true;
  cfg.own_change = [](int t) { return t >= kChange ? 0.25 * (t - kChange + 1) : 0.0; };
  std::vector<JudgedInput> out;
  for (auto& o : alarms::test::make_run(cfg)) {
    JudgedInput in;
    in.asset_group = kGroup;
    in.time_scale = TimeScale::Condition;
    in.channel_names = alarms::test::channel_names4();
    in.factor_names = alarms::test::factor_names4();
    in.lag_order = 1;
    in.observation = std::move(o);
    out.push_back(std::move(in));
  }
  return out;
}

std::vector<Judgement> judge_all(AlarmDesk& desk, const std::vector<JudgedInput>& in, std::size_t from, std::size_t to) {
  std::vector<Judgement> out;
  for (std::size_t t = from; t < to; ++t) out.push_back(desk.judge(in[t]));
  return out;
}

TEST(AlarmDesk, DegradingChannelRaisesWithActionAndNextLevel) {
  const auto in = degrading_stream();
  AlarmDesk desk(RecommenderParams{}, "");
  const auto judged = judge_all(desk, in, 0, in.size());

  // The same observations through an engine of the same parameters: the events the desk must report.
  alarms::AlarmEngine reference(kGroup, in[0].channel_names, in[0].factor_names, RecommenderParams{}.condition);
  std::size_t raises = 0, learned = 0, advised = 0;
  const EventJudgement* first_raise = nullptr;
  for (std::size_t t = 0; t < in.size(); ++t) {
    const auto expected = reference.observe(in[t].observation);
    const Judgement& j = judged[t];
    ASSERT_TRUE(j.judged) << t;
    EXPECT_EQ(j.opened, t == 0) << t;
    learned += j.baseline_learned ? 1 : 0;
    ASSERT_EQ(j.events.size(), expected.size()) << t;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      const EventJudgement& e = j.events[i];
      EXPECT_EQ(e.event.alarm_id, expected[i].alarm_id);
      EXPECT_EQ(e.event.state, expected[i].state);
      const bool degradation = e.event.category == alarms::category::kDegradation;
      EXPECT_EQ(e.advised, degradation && e.event.state != alarms::AlarmState::Cleared) << e.event.alarm_id;
      if (e.advised) {
        ++advised;
        EXPECT_FALSE(e.decision.action.empty()) << e.event.alarm_id;
        EXPECT_FALSE(e.decision.items.empty()) << e.event.alarm_id;
      }
      if (degradation && e.event.state == alarms::AlarmState::Raised) {
        ++raises;
        if (first_raise == nullptr) first_raise = &e;
      }
    }
    // The status facts name the group's engine at this observation.
    EXPECT_NE(j.status.condition, nullptr);
    EXPECT_EQ(j.status.sample, nullptr);
    EXPECT_EQ(j.status.index, in[t].observation.index);
    EXPECT_TRUE(j.prognoses_judged);
  }
  EXPECT_TRUE(judged[0].opened && !judged[0].resumed);
  EXPECT_EQ(judged[0].learning_observations, 140);  // warmup 20 + baseline 120 (AlarmParams defaults)
  EXPECT_EQ(learned, 1u);
  ASSERT_NE(first_raise, nullptr);
  EXPECT_GE(first_raise->event.index, static_cast<std::uint64_t>(kChange));
  EXPECT_EQ(first_raise->event.channel, 1);  // bearing 2 degrades
  EXPECT_EQ(first_raise->decision.act_on, 1);
  // Its next level (the Alarm decision fields) with the PROGNOSIS text naming the channel as the alarm does.
  ASSERT_TRUE(first_raise->has_next_level);
  EXPECT_GT(first_raise->next_level.ratio, 1.0);
  EXPECT_EQ(first_raise->next_level_text.rfind("bearing 2", 0), 0u) << first_raise->next_level_text;
  EXPECT_NE(first_raise->next_level_text.find("x its baseline)"), std::string::npos) << first_raise->next_level_text;
  // One prognosis per level (warning, critical, end of life) of every channel with an open degradation alarm (the
  // reference engine's: bearing 2, and bearing 3 which it drives), each with its text naming the channel.
  std::set<int> open_channels;
  for (const auto& e : reference.active_alarms()) {
    if (e.category == alarms::category::kDegradation) open_channels.insert(e.channel);
  }
  ASSERT_EQ(open_channels.count(1), 1u);
  const Judgement& last = judged.back();
  ASSERT_EQ(last.prognoses.size(), 3 * open_channels.size());
  for (const auto& p : last.prognoses) {
    const std::string name = in[0].channel_names.at(static_cast<std::size_t>(p.prognosis.channel));
    EXPECT_EQ(open_channels.count(p.prognosis.channel), 1u);
    EXPECT_EQ(p.channel_name, name);
    EXPECT_EQ(p.index, in.back().observation.index);
    EXPECT_EQ(p.text.rfind(name, 0), 0u) << p.text;
  }
  EXPECT_FALSE(last.status.prognosis(first_raise->event).empty());
  const auto summary = desk.summaries();
  ASSERT_EQ(summary.size(), 1u);
  EXPECT_EQ(summary[0].raised, raises);
  EXPECT_EQ(summary[0].observations, in.size());
  EXPECT_GT(advised, 0u);
}

TEST(AlarmDesk, DuplicateIndexIsDroppedAndCounted) {
  const auto in = degrading_stream();
  AlarmDesk desk(RecommenderParams{}, "");
  judge_all(desk, in, 0, 10);
  const Judgement again = desk.judge(in[5]);
  EXPECT_TRUE(again.duplicate);
  EXPECT_FALSE(again.judged);
  EXPECT_TRUE(again.events.empty());
  EXPECT_EQ(desk.store().duplicates(), 1u);
  EXPECT_EQ(desk.summaries().at(0).observations, 10u);  // the engine never saw it
  const Judgement next = desk.judge(in[10]);
  EXPECT_TRUE(next.judged);
  EXPECT_EQ(desk.store().duplicates(), 1u);
}

TEST(AlarmDesk, SwitchedOffTimeScaleIsNotJudged) {
  RecommenderParams p;
  p.condition_enabled = false;
  AlarmDesk desk(p, "");
  const auto in = degrading_stream();
  const Judgement j = desk.judge(in[0]);
  EXPECT_FALSE(j.judged || j.opened || j.duplicate);
  EXPECT_TRUE(desk.summaries().empty());
}

TEST(AlarmDesk, RestoredCheckpointResumesWhereItStopped) {
  const auto in = degrading_stream();
  const std::size_t stop = 470;  // after the raise: the checkpoint holds an open alarm
  TempDir dir;
  AlarmDesk never_stopped(RecommenderParams{}, "");
  const auto truth = judge_all(never_stopped, in, 0, in.size());
  std::size_t active_at_stop = 0;
  {
    AlarmDesk first(RecommenderParams{}, dir.path.string());
    judge_all(first, in, 0, stop);
    active_at_stop = first.summaries().at(0).active;
  }  // dropped without any shutdown step, as after kill -9
  ASSERT_GT(active_at_stop, 0u);
  AlarmDesk second(RecommenderParams{}, dir.path.string());
  const auto resumed = second.restore();
  ASSERT_EQ(resumed.size(), 1u);
  EXPECT_EQ(resumed[0].asset_group, kGroup);
  EXPECT_EQ(resumed[0].time_scale, TimeScale::Condition);
  EXPECT_EQ(resumed[0].observations, stop);
  EXPECT_EQ(resumed[0].active_alarms, active_at_stop);
  EXPECT_FALSE(resumed[0].republish.empty());
  EXPECT_TRUE(resumed[0].prognoses_judged);
  ASSERT_FALSE(resumed[0].prognoses.empty());
  EXPECT_EQ(resumed[0].prognoses[0].index, stop - 1);  // the last observation the checkpoint holds
  // The last index is a duplicate; the next ones give exactly what the desk that never stopped gave.
  EXPECT_TRUE(second.judge(in[stop - 1]).duplicate);
  for (std::size_t t = stop; t < in.size(); ++t) {
    const Judgement j = second.judge(in[t]);
    ASSERT_TRUE(j.judged && !j.opened) << t;
    ASSERT_EQ(j.events.size(), truth[t].events.size()) << t;
    for (std::size_t i = 0; i < j.events.size(); ++i) {
      EXPECT_EQ(j.events[i].event.alarm_id, truth[t].events[i].event.alarm_id);
      EXPECT_EQ(j.events[i].event.state, truth[t].events[i].event.state);
      EXPECT_EQ(j.events[i].next_level_text, truth[t].events[i].next_level_text);
    }
    ASSERT_EQ(j.prognoses.size(), truth[t].prognoses.size()) << t;
    for (std::size_t i = 0; i < j.prognoses.size(); ++i) EXPECT_EQ(j.prognoses[i].text, truth[t].prognoses[i].text);
  }
}

TEST(AlarmDesk, RestoredCheckpointOfOtherChannelsIsRefusedNamingTheFile) {
  const auto in = degrading_stream();
  TempDir dir;
  {
    AlarmDesk first(RecommenderParams{}, dir.path.string());
    judge_all(first, in, 0, 5);
  }
  AlarmDesk second(RecommenderParams{}, dir.path.string());
  ASSERT_EQ(second.restore().size(), 1u);
  JudgedInput other = in[5];
  other.channel_names[0] = "another bearing";
  try {
    second.judge(other);
    FAIL() << "a checkpoint of other channels was used";
  } catch (const estimation::StateError& e) {
    EXPECT_NE(std::string(e.what()).find("ims2.condition.alarms.state"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace causal::advice
