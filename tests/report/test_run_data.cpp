// Reading a recorder folder back: file discovery, factor names, series, alarm spans.
#include "run_data.hpp"
#include "causal/io/file_names.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace causal::report;

namespace {

const double kT0 = 1076581959.0;  // 2004-02-12 10:32:39 UTC

struct TempDir : causal::test::TestTempDir {
  TempDir() : TestTempDir("causal_report_run") {}
};

AlarmRecord row(const std::string& id, const std::string& state, Severity sev, int channel,
                std::optional<double> time, std::optional<double> raised, std::optional<double> cleared) {
  AlarmRecord r;
  r.alarm_id = id;
  r.state = state;
  r.severity = sev;
  r.kind = "feature_drift";
  r.channel = channel;
  r.time = time;
  r.raised = raised;
  r.cleared = cleared;
  r.raised_utc = raised ? "r" : "";
  r.cleared_utc = cleared ? "c" : "";
  return r;
}

}  // namespace

TEST(ParseFactorName, FollowsTheModelConvention) {
  auto check = [](const std::string& name, int g, int k, int j, int lag) {
    const auto f = parse_factor_name(name, g);
    ASSERT_TRUE(f.has_value()) << name;
    EXPECT_EQ(f->outcome, k) << name;
    EXPECT_EQ(f->source, j) << name;
    EXPECT_EQ(f->lag, lag) << name;
  };
  check("x12", 4, 1, 2, 0);
  check("xL13", 4, 1, 3, 1);
  check("xL11", 4, 1, 1, 1);
  check("xL243", 4, 4, 3, 2);
  check("x10_2", 12, 10, 2, 0);
  check("xL10_12", 12, 10, 12, 1);
  check("xL3_10_2", 12, 10, 2, 3);
  EXPECT_FALSE(parse_factor_name("x15", 4).has_value());  // channel 5 of 4
  EXPECT_FALSE(parse_factor_name("sd_x12", 4).has_value());
  EXPECT_FALSE(parse_factor_name("index", 4).has_value());
  EXPECT_FALSE(parse_factor_name("x123", 4).has_value());  // instantaneous names have exactly k and j
  EXPECT_FALSE(parse_factor_name("xL112", 4).has_value()); // "lag 1" is never written out
}

TEST(DiscoverRun, FindsAssetsFromFileNamesAndAlarms) {
  TempDir dir;
  dir.write("conditions_ims2_shaft_1_rms.csv", "snapshot,time_ns,time_utc,B1\n");
  dir.write("conditions_ims2_shaft_1_kurtosis.csv", "snapshot,time_ns,time_utc,B1\n");
  dir.write("factors_ims2_shaft_1_condition_filter.csv", "index\n");
  dir.write("factors_ims2_shaft_1_condition_fixed-lag.csv", "index\n");
  dir.write("factors_ims2_shaft_1_sample_filter.csv", "index\n");
  dir.write("factors_other_sample_filter.csv", "index\n");
  dir.write("alarms.csv",
            "alarm_id,state,severity,kind,asset_group,channel,channel_name,sample_index,time_utc,raised_utc,"
            "cleared_utc,root_cause_channel,root_cause_name,score,threshold,reason\n"
            "id,raised,warning,k,\"only in alarms, this one\",1,B1,0,,,,0,,1,1,r\n");
  dir.write("notes.txt", "x");
  const RunFiles run = discover_run(dir.path);
  EXPECT_EQ(run.csv_count, 7u);
  EXPECT_EQ(run.alarms, dir.path / "alarms.csv");
  ASSERT_EQ(run.assets.size(), 2u);
  const AssetFiles& a = run.assets[0];
  EXPECT_EQ(a.asset, "ims2_shaft_1");
  ASSERT_EQ(a.conditions.size(), 2u);
  EXPECT_EQ(a.conditions[0].first, "kurtosis");
  EXPECT_EQ(a.conditions[1].first, "rms");
  EXPECT_EQ(a.factors_filter, dir.path / "factors_ims2_shaft_1_condition_filter.csv");
  EXPECT_EQ(a.factors_fixed_lag, dir.path / "factors_ims2_shaft_1_condition_fixed-lag.csv");
  // Named as its recorder files would be (the one sanitiser, causal/io/file_names.hpp): odd bytes + a hash.
  EXPECT_EQ(run.assets[1].asset, causal::io::safe_file_component("only in alarms, this one"));
  EXPECT_EQ(run.assets[1].asset.substr(0, 25), "only_in_alarms__this_one-");
}

TEST(LoadSeries, ConditionsAndFactorsWithMissingCells) {
  TempDir dir;
  dir.write("c.csv", "snapshot,time_ns,time_utc,Bearing 1,Bearing 2\n"
                     "0,1076581959000000000,2004-02-12 10:32:39,0.5,0.25\n"
                     "1,,2004-02-12 10:42:39,0.75,\n");
  const ConditionSeries c = load_conditions(dir.path / "c.csv", "rms");
  EXPECT_EQ(c.channels, (std::vector<std::string>{"Bearing 1", "Bearing 2"}));
  ASSERT_EQ(c.t.size(), 2u);
  EXPECT_DOUBLE_EQ(c.t[0], kT0);
  EXPECT_DOUBLE_EQ(c.t[1], kT0 + 600.0);  // from time_utc when time_ns is empty
  EXPECT_EQ(c.values[0][1], 0.75);
  EXPECT_TRUE(std::isnan(c.values[1][1]));

  dir.write("f.csv", "index,time_ns,time_utc,x12,xL11,xL12,x21,xL21,xL22,sd_x12,sd_xL11,sd_xL12,sd_x21,sd_xL21,"
                     "sd_xL22,nis_Bearing 1,nis_Bearing 2\n"
                     "0,1076581959000000000,x,1,2,3,4,5,6,0.1,0.2,0.3,0.4,0.5,0.6,1,1\n"
                     "1,1076582559000000000,x,7,8,9,,,,0.7,0.8,0.9,,,,1,\n");
  const FactorSeries f = load_factors(dir.path / "f.csv", "filter");
  EXPECT_EQ(f.outcome_names, (std::vector<std::string>{"Bearing 1", "Bearing 2"}));
  EXPECT_EQ(f.names, (std::vector<std::string>{"x12", "xL11", "xL12", "x21", "xL21", "xL22"}));
  EXPECT_EQ(f.outcome, (std::vector<int>{0, 0, 0, 1, 1, 1}));
  ASSERT_EQ(f.t.size(), 2u);
  EXPECT_EQ(f.mean[2][1], 9.0);
  EXPECT_EQ(f.sd[4][0], 0.5);
  EXPECT_TRUE(std::isnan(f.mean[3][1]));
}

TEST(LoadAlarms, FiltersByAssetAndParsesTimes) {
  TempDir dir;
  dir.write("alarms.csv",
            "alarm_id,state,severity,kind,asset_group,channel,channel_name,sample_index,time_utc,raised_utc,"
            "cleared_utc,root_cause_channel,root_cause_name,score,threshold,reason\n"
            "a/2/k/1,raised,warning,feature_drift,a/b,2,Bearing 2,5,2004-02-12 10:32:39,2004-02-12 10:32:39,,3,"
            "Bearing 3,2,1,\"up, \"\"a lot\"\"\"\n"
            "z/1/k/1,raised,critical,feature_drift,z,1,Bearing 1,5,,2004-02-12 10:32:39,,0,,2,1,r\n");
  const auto rows = load_alarms(dir.path / "alarms.csv", causal::io::safe_file_component("a/b"));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].severity, Severity::Warning);
  EXPECT_EQ(rows[0].channel, 2);
  EXPECT_EQ(rows[0].root_cause_channel, 3);
  EXPECT_EQ(rows[0].root_cause_name, "Bearing 3");
  EXPECT_EQ(rows[0].reason, "up, \"a lot\"");
  ASSERT_TRUE(rows[0].raised.has_value());
  EXPECT_DOUBLE_EQ(*rows[0].raised, kT0);
  EXPECT_FALSE(rows[0].cleared.has_value());
  EXPECT_EQ(load_alarms(dir.path / "alarms.csv", "").size(), 2u);
}

TEST(BuildAlarmSpans, SegmentsFollowEscalationAndClearing) {
  const std::vector<AlarmRecord> rows{
      row("A", "raised", Severity::Advisory, 2, kT0 + 100, kT0 + 100, std::nullopt),
      row("B", "raised", Severity::Warning, 3, kT0 + 150, kT0 + 150, std::nullopt),
      row("A", "escalated", Severity::Critical, 2, kT0 + 300, kT0 + 100, std::nullopt),
      row("A", "cleared", Severity::Critical, 2, kT0 + 500, kT0 + 100, kT0 + 500),
      row("B", "escalated", Severity::Critical, 3, std::nullopt, kT0 + 150, std::nullopt),  // time unknown
  };
  const auto spans = build_alarm_spans(rows, kT0 + 1000);
  ASSERT_EQ(spans.size(), 2u);
  const AlarmSpan& a = spans[0];
  EXPECT_EQ(a.alarm_id, "A");
  EXPECT_EQ(a.first_severity, Severity::Advisory);
  EXPECT_EQ(a.max_severity, Severity::Critical);
  ASSERT_EQ(a.segments.size(), 2u);
  EXPECT_DOUBLE_EQ(a.segments[0].from, kT0 + 100);
  EXPECT_DOUBLE_EQ(a.segments[0].to, kT0 + 300);
  EXPECT_EQ(a.segments[0].severity, Severity::Advisory);
  EXPECT_DOUBLE_EQ(a.segments[1].to, kT0 + 500);
  EXPECT_EQ(a.segments[1].severity, Severity::Critical);
  const AlarmSpan& b = spans[1];
  EXPECT_FALSE(b.cleared.has_value());
  EXPECT_EQ(b.max_severity, Severity::Critical);
  ASSERT_EQ(b.segments.size(), 1u);  // the escalation has no time: not placed
  EXPECT_DOUBLE_EQ(b.segments[0].to, kT0 + 1000);
  EXPECT_EQ(b.segments[0].severity, Severity::Warning);
}
