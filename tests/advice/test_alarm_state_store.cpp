// causal::advice::AlarmStateStore (common/advice/src/alarm_state_store.cpp): alarm-recommender's
// checkpoints. A "restart" here is a second store on the same directory after the first one and its engine
// were dropped without any shutdown step (as after kill -9); the truth is the same stream through one
// engine that never stopped.
#include "causal/advice/alarm_state_store.hpp"

#include "../alarms/synthetic_group.hpp"
#include "causal/estimation/state_archive.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace causal::alarms {
namespace {

using causal::advice::AlarmStateStore;

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
struct TempDir {
  fs::path path;
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() /
           ("alarm_state_store_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

const std::string kGroup = "ims2/shaft 1";

// Channel 2's own noise steps up by 8 sigma over 400..439: raises, stays active, clears after 440.
std::vector<Observation> stream() {
  causal::alarms::test::SyntheticConfig cfg;
  cfg.seed = 4;
  cfg.own_change = [](int t) { return t >= 400 && t < 440 ? 8.0 : 0.0; };
  return causal::alarms::test::make_run(cfg);
}

// Feeds obs[from, to) the way AlarmDesk::judge does: duplicate check, observe, record.
std::vector<AlarmEvent> feed(AlarmStateStore& store, AlarmEngine& engine, bool sample, const std::vector<Observation>& obs,
                             std::size_t from, std::size_t to) {
  std::vector<AlarmEvent> all;
  for (std::size_t t = from; t < to; ++t) {
    if (store.is_duplicate(kGroup, sample, obs[t].index)) continue;
    const auto events = engine.observe(obs[t]);
    store.record(kGroup, sample, obs[t].index, events);
    all.insert(all.end(), events.begin(), events.end());
  }
  return all;
}

std::uint64_t observations_in_checkpoint(const std::string& file, const AlarmParams& p) {
  AlarmStateStore reader(fs::path(file).parent_path().string());
  return reader.open(kGroup, true, causal::alarms::test::channel_names4(), {}, p).engine->observations_seen();
}

}  // namespace

TEST(AlarmStateStore, FileNamesAreSanitisedAndDistinct) {
  EXPECT_EQ(AlarmStateStore::sanitise("ims2-shaft1"), "ims2-shaft1");
  const std::string a = AlarmStateStore::sanitise("ims2/shaft 1"), b = AlarmStateStore::sanitise("ims2_shaft_1");
  EXPECT_EQ(a.substr(0, 12), "ims2_shaft_1");
  EXPECT_EQ(a.size(), 12u + 9u) << a;  // "-" and 8 hex digits: something was replaced
  EXPECT_NE(a, b);
  EXPECT_EQ(AlarmStateStore::sanitise("..").find('/'), std::string::npos);
  EXPECT_NE(AlarmStateStore::sanitise("..")[0], '.');
  TempDir dir;
  AlarmStateStore store(dir.path.string());  // creates the directory
  EXPECT_TRUE(fs::is_directory(dir.path));
  EXPECT_EQ(store.path("ims2-shaft1", false), (dir.path / "ims2-shaft1.condition.alarms.state").string());
  EXPECT_EQ(store.path("ims2-shaft1", true), (dir.path / "ims2-shaft1.sample.alarms.state").string());
}

TEST(AlarmStateStore, WithoutDirectoryNothingIsWrittenButDuplicatesAreDropped) {
  AlarmStateStore store("");
  EXPECT_FALSE(store.enabled());
  auto opened = store.open(kGroup, false, causal::alarms::test::channel_names4(), {}, AlarmParams{});
  EXPECT_FALSE(opened.resumed);
  const auto obs = stream();
  feed(store, *opened.engine, false, obs, 0, 10);
  feed(store, *opened.engine, false, obs, 5, 12);  // 5..9 again: 5 duplicates, 10 and 11 are new
  EXPECT_EQ(store.duplicates(), 5u);
  EXPECT_EQ(opened.engine->observations_seen(), 12u);
  EXPECT_EQ(store.saves(), 0u);
}

// Condition level: killed while an alarm is active, restarted, the estimator re-sends the last 3
// observations. The restarted engine continues as the uninterrupted one, the re-sent observations are
// dropped, and the last event of every alarm id published before the crash is handed back for republishing.
TEST(AlarmStateStore, RestartResumesWhereItStoppedAndRepublishesLastEvents) {
  TempDir dir;
  const AlarmParams p;
  const auto obs = stream();
  const auto names = causal::alarms::test::channel_names4();
  AlarmEngine reference("ims2/shaft 1", names, {}, p);
  std::vector<AlarmEvent> expected;
  for (const auto& o : obs)
    for (auto& e : reference.observe(o)) expected.push_back(std::move(e));

  const std::size_t cut = 420;  // during the fault: alarms active
  std::map<std::string, AlarmEvent> last_before;
  {
    AlarmStateStore store(dir.path.string());
    auto opened = store.open(kGroup, false, names, {}, p);
    EXPECT_FALSE(opened.resumed);
    for (const auto& e : feed(store, *opened.engine, false, obs, 0, cut)) last_before[e.alarm_id] = e;
    EXPECT_EQ(store.saves(), cut);
  }  // no flush: condition level writes every observation
  ASSERT_FALSE(last_before.empty()) << "the scenario must have alarms before the cut";

  AlarmStateStore store(dir.path.string());
  auto opened = store.open(kGroup, false, names, {}, p);
  ASSERT_TRUE(opened.resumed);
  EXPECT_EQ(opened.engine->observations_seen(), cut);
  ASSERT_EQ(opened.republish.size(), last_before.size());
  for (const auto& e : opened.republish) {
    ASSERT_EQ(last_before.count(e.alarm_id), 1u) << e.alarm_id;
    const AlarmEvent& want = last_before[e.alarm_id];
    EXPECT_EQ(e.state, want.state) << e.alarm_id;
    EXPECT_EQ(e.severity, want.severity) << e.alarm_id;
    EXPECT_EQ(e.index, want.index) << e.alarm_id;
    EXPECT_EQ(e.reason, want.reason) << e.alarm_id;
  }
  const auto after = feed(store, *opened.engine, false, obs, cut - 3, obs.size());
  EXPECT_EQ(store.duplicates(), 3u);
  std::vector<AlarmEvent> expected_after;
  for (const auto& e : expected)
    if (e.index >= cut) expected_after.push_back(e);
  ASSERT_EQ(after.size(), expected_after.size());
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].alarm_id, expected_after[i].alarm_id);
    EXPECT_EQ(after[i].state, expected_after[i].state);
    EXPECT_EQ(after[i].index, expected_after[i].index);
    EXPECT_EQ(after[i].reason, expected_after[i].reason);
  }
  EXPECT_EQ(opened.engine->active_alarms().size(), reference.active_alarms().size());
}

// Sample level: at most one write per interval (here one hour, so only the first observation and the
// event-producing ones are written), flush() writes the rest.
TEST(AlarmStateStore, SampleLevelIsThrottledButEventsAreWrittenAtOnce) {
  TempDir dir;
  const AlarmParams p = AlarmParams::sample_level(50);
  auto obs = stream();
  for (auto& o : obs) {
    o.mean_nis.resize(4);
    for (int k = 0; k < 4; ++k) o.mean_nis(k) = 0.5 + o.innovations(k) * o.innovations(k) / o.innovation_variances(k);
  }
  const auto names = causal::alarms::test::channel_names4();
  AlarmStateStore store(dir.path.string(), std::chrono::hours(1));
  auto opened = store.open(kGroup, true, names, {}, p);
  const std::string file = store.path(kGroup, true);
  feed(store, *opened.engine, true, obs, 0, 10);
  EXPECT_EQ(store.saves(), 1u);
  EXPECT_EQ(observations_in_checkpoint(file, p), 1u);
  std::size_t t = 10;
  for (; t < obs.size(); ++t)
    if (!feed(store, *opened.engine, true, obs, t, t + 1).empty()) break;
  ASSERT_LT(t, obs.size()) << "the fault must raise an alarm";
  EXPECT_EQ(store.saves(), 2u);
  EXPECT_EQ(observations_in_checkpoint(file, p), t + 1) << "written at once, before the event is published";
  feed(store, *opened.engine, true, obs, t + 1, t + 5);
  store.flush();
  EXPECT_EQ(observations_in_checkpoint(file, p), t + 5);
}

TEST(AlarmStateStore, UnusableCheckpointsAreRefusedNamingTheFile) {
  TempDir dir;
  const AlarmParams p;
  const auto names = causal::alarms::test::channel_names4();
  const auto obs = stream();
  std::string file;
  {
    AlarmStateStore store(dir.path.string());
    auto opened = store.open(kGroup, false, names, {}, p);
    feed(store, *opened.engine, false, obs, 0, 50);
    file = store.path(kGroup, false);
  }
  auto refused = [&](const AlarmParams& params, const std::vector<std::string>& channels, const std::string& why) {
    AlarmStateStore store(dir.path.string());
    try {
      store.open(kGroup, false, channels, {}, params);
      ADD_FAILURE() << "accepted: " << why;
    } catch (const estimation::StateError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file), std::string::npos) << what;
      EXPECT_NE(what.find(why), std::string::npos) << what;
    }
  };
  AlarmParams other = p;
  other.cusum_k = 2.0;
  refused(other, names, "cusum_k: 1.5 -> 2");
  auto renamed = names;
  renamed[3] = "bearing 5";
  refused(p, renamed, "bearing 5");
  // Truncated file (a torn write that escaped the rename): the checksum / length check refuses it.
  const auto size = fs::file_size(file);
  fs::resize_file(file, size - 10);
  refused(p, names, "truncated");
}

}  // namespace causal::alarms
