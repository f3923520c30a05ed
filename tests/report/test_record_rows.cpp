// What the recorder writes per topic: file names, condition / alarm / recommendation rows, quoting.
#include "record_rows.hpp"
#include "row_cells.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"

#include <gtest/gtest.h>

#include <limits>

using namespace causal::recorder;
using causal::io::csv_line;

namespace {
const std::int64_t kT0 = 1076581959LL * 1000000000LL;  // 2004-02-12 10:32:39 UTC
const std::int64_t kMin = 60LL * 1000000000LL;

causal_twin::Alarm make_alarm() {
  causal_twin::Alarm a;
  a.alarm_id("plant/a,b/2/feature_drift/1");
  a.asset_group("plant/a,b");
  a.channel(2);
  a.channel_name("Bearing 2");
  a.severity(causal_twin::WARNING);
  a.state(causal_twin::RAISED);
  a.kind("feature_drift");
  a.raised_time_ns(kT0 + 10 * kMin);
  a.cleared_time_ns(0);
  a.sample_index(17);
  a.root_cause_channel(3);
  a.root_cause_name("Bearing 3");
  a.score(12.5);
  a.threshold(8.0);
  a.reason("rms rose 3x, \"sharply\"\nsince 10:42");
  a.category("degradation");
  a.root_cause_confidence(0.75);
  return a;
}
}  // namespace

TEST(RecordRows, FileNamesAreSanitised) {
  // Safe names as they are; any other byte becomes '_' and a hash of the name follows (causal/io/file_names.hpp),
  // so "a b" and "a_b" never share a file.
  EXPECT_EQ(conditions_file_name("ims2/shaft 1", "rms"),
            "conditions_" + causal::io::safe_file_component("ims2/shaft 1") + "_rms.csv");
  EXPECT_EQ(conditions_file_name("ims2/shaft 1", "rms").substr(0, 24), "conditions_ims2_shaft_1-");
  EXPECT_NE(conditions_file_name("a b", "rms"), conditions_file_name("a_b", "rms"));
  EXPECT_EQ(factors_file_name("ims2-shaft1", causal_twin::CONDITION_LEVEL, causal_twin::FIXED_LAG_SMOOTHER),
            "factors_ims2-shaft1_condition_fixed-lag.csv");
  EXPECT_EQ(factors_file_name("a_b", causal_twin::SAMPLE_LEVEL, causal_twin::FILTER), "factors_a_b_sample_filter.csv");
}

TEST(RecordRows, ConditionRow) {
  causal_twin::ConditionVector c;
  c.asset_group("g");
  c.feature("rms");
  c.snapshot_index(7);
  c.time_ns(kT0);
  c.channel_names({"Bearing 1", "B,2"});
  c.values({0.125, 1e-7});
  EXPECT_EQ(csv_line(condition_header(c)), "snapshot,time_ns,time_utc,Bearing 1,\"B,2\"\n");
  EXPECT_EQ(csv_line(condition_row(c)), "7," + std::to_string(kT0) + ",2004-02-12 10:32:39,0.125,1e-07\n");
}

TEST(RecordRows, AlarmRowQuotesTextAndFormatsTimes) {
  const auto a = make_alarm();
  ASSERT_EQ(header_of<causal_twin::Alarm>().size(), 22u);
  EXPECT_EQ(csv_line(header_of<causal_twin::Alarm>()),
            "alarm_id,state,severity,kind,asset_group,channel,channel_name,sample_index,time_utc,raised_utc,"
            "cleared_utc,root_cause_channel,root_cause_name,score,threshold,reason,category,root_cause_confidence,"
            "next_level,hours_to_next_level,hours_to_next_level_low,hours_to_next_level_high\n");
  EXPECT_EQ(csv_line(alarm_row(a, std::nullopt)),
            "\"plant/a,b/2/feature_drift/1\",raised,warning,feature_drift,\"plant/a,b\",2,Bearing 2,17,"
            "2004-02-12 10:42:39,2004-02-12 10:42:39,,3,Bearing 3,12.5,8,"
            "\"rms rose 3x, \"\"sharply\"\"\nsince 10:42\",degradation,0.75,,,,\n");
}

TEST(RecordRows, AlarmRowCarriesTheNextLevel) {
  auto a = make_alarm();
  a.next_level("critical");
  a.hours_to_next_level(12.5);
  a.hours_to_next_level_low(8.25);
  a.hours_to_next_level_high(std::numeric_limits<double>::quiet_NaN());  // unbounded: empty
  const auto row = alarm_row(a, std::nullopt);
  ASSERT_EQ(row.size(), 22u);
  EXPECT_EQ(row[18], "critical");
  EXPECT_EQ(row[19], "12.5");
  EXPECT_EQ(row[20], "8.25");
  EXPECT_EQ(row[21], "");
}

TEST(RecordRows, PrognosisRowStartsWithTheInterfaceColumns) {
  const std::string head = csv_line(header_of<causal_twin::Prognosis>());
  EXPECT_EQ(head.rfind("asset_group,channel,channel_name,sample_index,time_utc,level,hours,hours_low,hours_high,", 0), 0u)
      << head;
  causal_twin::Prognosis p;
  p.asset_group("ims2");
  p.channel(1);
  p.channel_name("bearing1");
  p.level("critical");
  p.sample_index(600);
  p.time_ns(kT0);
  p.known(true);
  p.hours(10.5);
  p.hours_low(6.0);
  p.hours_high(20.0);
  p.eta_time_ns(kT0 + 630 * kMin);
  const auto row = row_of(p);
  ASSERT_EQ(row.size(), header_of<causal_twin::Prognosis>().size());
  EXPECT_EQ(row[0], "ims2");
  EXPECT_EQ(row[1], "1");
  EXPECT_EQ(row[3], "600");
  EXPECT_EQ(row[4], "2004-02-12 10:32:39");
  EXPECT_EQ(row[5], "critical");
  EXPECT_EQ(row[6], "10.5");
  EXPECT_EQ(row[7], "6");
  EXPECT_EQ(row[8], "20");
  p.known(false);
  p.hours(std::numeric_limits<double>::quiet_NaN());
  p.hours_low(std::numeric_limits<double>::quiet_NaN());
  p.hours_high(std::numeric_limits<double>::quiet_NaN());
  const auto unknown = row_of(p);
  EXPECT_EQ(unknown[6], "");
  EXPECT_EQ(unknown[7], "");
  EXPECT_EQ(unknown[8], "");
}

TEST(RecordRows, PrognosisLedgerWritesEachKeyAndSnapshotOnce) {
  PrognosisLedger ledger;
  causal_twin::Prognosis p;
  p.asset_group("g");
  p.channel(1);
  p.level("warning");
  p.sample_index(10);
  EXPECT_TRUE(ledger.accept(p));
  EXPECT_FALSE(ledger.accept(p));  // re-published after a restart
  p.level("critical");
  EXPECT_TRUE(ledger.accept(p));   // another key
  p.sample_index(11);
  EXPECT_TRUE(ledger.accept(p));
  p.sample_index(9);
  EXPECT_FALSE(ledger.accept(p));  // replayed history
}

TEST(RecordRows, AlarmEventTimeFollowsTheState) {
  auto a = make_alarm();
  a.state(causal_twin::ESCALATED);
  a.severity(causal_twin::CRITICAL);
  EXPECT_EQ(alarm_row(a, std::nullopt)[8], "");  // escalation time unknown
  EXPECT_EQ(alarm_row(a, kT0 + 30 * kMin)[8], "2004-02-12 11:02:39");
  EXPECT_EQ(alarm_row(a, std::nullopt)[2], "critical");
  a.state(causal_twin::CLEARED);
  a.cleared_time_ns(kT0 + 50 * kMin);
  const auto row = alarm_row(a, kT0 + 30 * kMin);
  EXPECT_EQ(row[1], "cleared");
  EXPECT_EQ(row[8], "2004-02-12 11:22:39");
  EXPECT_EQ(row[10], "2004-02-12 11:22:39");
}

TEST(RecordRows, RecommendationRowHasEveryField) {
  causal_twin::Recommendation r;
  r.recommendation_id("x/1");
  r.alarm_id("x");
  r.asset_group("g");
  r.rank(1);
  r.target_channel(2);
  r.intervene_channel(3);
  r.delta(-0.5);
  r.effect_immediate(-0.25);
  r.effect_steady_state(-0.4);
  r.effect_low(-0.6);
  r.effect_high(-0.2);
  r.confidence(0.9);
  r.text("reduce load on Bearing 3, then re-check");
  r.answer_kind("horizon");
  r.horizon_snapshots(12);
  r.spectral_radius(0.993);
  r.draws(400);
  r.unstable_draws(37);
  r.unstable_draw_share(0.0925);
  r.effect_median(-0.3);
  r.effect_percent(-25.9);
  r.effect_percent_low(-45.1);
  r.effect_percent_high(-18.1);
  r.effect_level_change(-0.02);
  r.reliable(true);
  r.summary("after 12 snapshots: -25.9 % [-45.1, -18.1] (90 %)");
  r.sample_index(533);
  r.action("Reduce Bearing 3 by 10 %, then re-check");
  r.action_kind("upstream_lever");
  r.act_on_channel(3);
  r.act_on_name("Bearing 3");
  r.horizon_hours(2.0);
  r.order_confidence(0.92);
  r.order_source("learned");
  EXPECT_EQ(header_of<causal_twin::Recommendation>().size(), 34u);
  EXPECT_EQ(csv_line(row_of(r)),
            "x/1,x,g,1,2,3,-0.5,-0.25,-0.4,-0.6,-0.2,0.9,\"reduce load on Bearing 3, then re-check\",horizon,12,0.993,400,37,"
            "0.0925,-0.3,-25.9,-45.1,-18.1,-0.02,true,\"after 12 snapshots: -25.9 % [-45.1, -18.1] (90 %)\",533,"
            "\"Reduce Bearing 3 by 10 %, then re-check\",upstream_lever,3,Bearing 3,2,0.92,learned\n");
}

TEST(IndexClock, RemembersTheNewestIndices) {
  IndexClock clock(3);
  for (std::uint64_t n = 0; n < 5; ++n) clock.record(n, kT0 + static_cast<std::int64_t>(n) * kMin);
  EXPECT_EQ(clock.size(), 3u);
  EXPECT_FALSE(clock.time_of(1).has_value());
  EXPECT_EQ(clock.time_of(4), kT0 + 4 * kMin);
}

TEST(RepeatFilter, OnlyAChangeOfTheLastSignaturePerIdIsNew) {
  RepeatFilter f;
  causal_twin::Alarm a = make_alarm();
  EXPECT_TRUE(f.accept(a.alarm_id(), alarm_signature(a)));
  EXPECT_FALSE(f.accept(a.alarm_id(), alarm_signature(a))) << "replayed last value";
  causal_twin::Alarm other = a;
  other.alarm_id("another");
  EXPECT_TRUE(f.accept(other.alarm_id(), alarm_signature(other))) << "same content, other id";
  a.reason("new wording");  // not part of the signature: still the same state change
  EXPECT_FALSE(f.accept(a.alarm_id(), alarm_signature(a)));
  a.sample_index(18);
  EXPECT_TRUE(f.accept(a.alarm_id(), alarm_signature(a))) << "new evidence";
  a.severity(causal_twin::CRITICAL);
  EXPECT_TRUE(f.accept(a.alarm_id(), alarm_signature(a)));
  a.state(causal_twin::CLEARED);
  EXPECT_TRUE(f.accept(a.alarm_id(), alarm_signature(a)));
  EXPECT_EQ(f.ids(), 2u);

  causal_twin::Recommendation r;
  r.recommendation_id("x/1");
  r.text("reduce load");
  EXPECT_TRUE(f.accept(r.recommendation_id(), recommendation_signature(r)));
  EXPECT_FALSE(f.accept(r.recommendation_id(), recommendation_signature(r)));
  r.effect_low(-0.3);
  EXPECT_TRUE(f.accept(r.recommendation_id(), recommendation_signature(r))) << "any field differs";
}

TEST(TopicCounts, DescribedForTheExitLog) {
  EXPECT_EQ(describe(TopicCounts{12, 9, 2, 1}), "received 12, written 9, duplicates 2, refused 1");
  EXPECT_EQ(describe_missing({{120, 131}, {140, 140}}, "snapshots"), "lost snapshots 120..131, 140");
  EXPECT_EQ(describe_missing({}, "snapshots"), "");
}
