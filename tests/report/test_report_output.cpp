// Report text outputs: gnuplot scripts (structure, data, alarm marks) and the Markdown summary.
#include "gnuplot_plots.hpp"
#include "report_builder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

using namespace causal::report;

namespace {

const double kT0 = 1076581959.0;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

AlarmSpan span(const std::string& id, int channel, Severity sev, double raised, std::optional<double> cleared,
               const std::string& root) {
  AlarmSpan s;
  s.alarm_id = id;
  s.kind = "feature_drift";
  s.channel = channel;
  s.channel_name = "Bearing " + std::to_string(channel);
  s.raised = raised;
  s.raised_utc = "2004-02-12 10:42:39";
  s.cleared = cleared;
  s.cleared_utc = cleared ? "2004-02-12 11:12:39" : "";
  s.first_severity = s.max_severity = sev;
  s.root_cause_name = root;
  s.segments.push_back({raised, cleared.value_or(kT0 + 3600), sev});
  return s;
}

}  // namespace

TEST(GnuplotQuote, DoublesSingleQuotes) {
  EXPECT_EQ(gnuplot_quote("it's"), "'it''s'");
  EXPECT_EQ(gnuplot_quote("a\nb"), "'a b'");
}

TEST(FactorTitle, NamesSourceAndOutcome) {
  const std::vector<std::string> ch{"B1", "B2", "B3"};
  EXPECT_EQ(factor_title("x12", ch), "x12:  B2 \xE2\x86\x92 B1");
  EXPECT_EQ(factor_title("xL33", ch), "xL33:  B3 (lag 1) \xE2\x86\x92 B3");
  EXPECT_EQ(factor_title("weird", ch), "weird");
}

TEST(ConditionTrendsScript, LogScaleDataAndAlarmLines) {
  ConditionSeries c;
  c.feature = "rms";
  c.channels = {"Bearing 1", "Bearing 2"};
  c.t = {kT0, kT0 + 600, kT0 + 1200};
  c.values = {{0.1, 0.2, std::nan("")}, {0.3, 0.4, 0.5}};
  const std::vector<AlarmSpan> alarms{span("A", 2, Severity::Critical, kT0 + 600, std::nullopt, "Bearing 1")};
  const std::string s =
      condition_trends_script("shaft", {c}, alarms, {kT0 - 10, kT0 + 1210}, PlotStyle{}, "/tmp/out it's.png");
  EXPECT_NE(s.find("set terminal pngcairo size 1400,900"), std::string::npos);
  EXPECT_NE(s.find("set output '/tmp/out it''s.png'"), std::string::npos);
  EXPECT_NE(s.find("set logscale y"), std::string::npos);
  EXPECT_NE(s.find("1076582559.000 0.2 0.4\n"), std::string::npos);
  EXPECT_NE(s.find("1076583159.000 NaN 0.5\n"), std::string::npos);
  EXPECT_EQ(count(s, "set arrow from 1076582559.000, graph 0"), 1u);
  EXPECT_NE(s.find("lc rgb '#D00000'"), std::string::npos);
  EXPECT_NE(s.find("title 'critical alarm'"), std::string::npos);
  EXPECT_NE(s.find("title 'Bearing 2'"), std::string::npos);

  c.values[0][0] = -1.0;  // a non-positive feature cannot go on a log axis
  PlotStyle gd;
  gd.pngcairo = false;
  const std::string lin = condition_trends_script("shaft", {c}, {}, {kT0 - 10, kT0 + 1210}, gd, "x.png");
  EXPECT_NE(lin.find("unset logscale y"), std::string::npos);
  EXPECT_NE(lin.find("set terminal png truecolor"), std::string::npos);
}

TEST(FactorPanelsScript, OnePanelPerFactorWithBandsForBothEstimators) {
  FactorSeries f;
  f.kind = "filter";
  f.t = {kT0, kT0 + 600};
  f.names = {"x12", "xL11", "xL12", "x21"};
  f.outcome = {0, 0, 0, 1};
  f.mean = {{0.5, 0.6}, {0.9, 0.8}, {-0.1, 0.0}, {0.2, 0.2}};
  f.sd = {{0.1, 0.1}, {0.05, 0.05}, {0.2, 0.2}, {0.1, 0.1}};
  f.outcome_names = {"Bearing 1", "Bearing 2"};
  FactorSeries l = f;
  l.kind = "fixed-lag";
  const std::string s = factor_panels_script("shaft", "Bearing 1", &f, &l, {0, 1, 2}, f.outcome_names, {}, 1,
                                             {kT0, kT0 + 600}, PlotStyle{}, "p.png", "");
  EXPECT_NE(s.find("set multiplot layout 1,3"), std::string::npos);
  EXPECT_EQ(count(s, "with filledcurves"), 6u);  // 3 panels x 2 estimators
  EXPECT_NE(s.find("x12:  Bearing 2 \xE2\x86\x92 Bearing 1"), std::string::npos);
  EXPECT_NE(s.find("xL11:  Bearing 1 (lag 1) \xE2\x86\x92 Bearing 1"), std::string::npos);
  // Filter block row: time, then (mean, sd) of the three page factors.
  EXPECT_NE(s.find("1076581959.000 0.5 0.1 0.9 0.05 -0.1 0.2\n"), std::string::npos);
  // Zero line only where zero is near the data: panel 3 (x in [-0.5, 0.4]) but not panel 2 (0.8..1.0).
  EXPECT_EQ(count(s, "0 with lines dt 3"), 1u);
  const std::string one = factor_panels_script("shaft", "Bearing 1", &f, nullptr, {0}, f.outcome_names, {}, 1,
                                               {kT0, kT0 + 600}, PlotStyle{}, "p.png", "");
  EXPECT_EQ(count(one, "with filledcurves"), 1u);
  EXPECT_EQ(one.find("$fixedlag"), std::string::npos);
}

TEST(AlarmTimelineScript, OneRowPerChannelAndDetectorLabelledOnTheAxis) {
  std::vector<AlarmSpan> alarms{span("A", 2, Severity::Warning, kT0 + 600, kT0 + 2400, "Bearing 3"),
                                span("B", 3, Severity::Advisory, kT0 + 1200, std::nullopt, ""),
                                span("C", 2, Severity::Advisory, kT0 + 3000, std::nullopt, "Bearing 2")};
  alarms[0].segments = {{kT0 + 600, kT0 + 1200, Severity::Warning}, {kT0 + 1200, kT0 + 2400, Severity::Critical}};
  alarms[1].kind = "innovation_nis";
  const std::string s = alarm_timeline_script("shaft", {"Bearing 1", "Bearing 2", "Bearing 3"}, alarms,
                                              {kT0, kT0 + 3600}, PlotStyle{}, "t.png");
  // Rows: Bearing 1 without alarms, Bearing 2 feature_drift (two episodes, two roots), Bearing 3 innovation_nis.
  EXPECT_NE(s.find("set ytics ('Bearing 1  (no alarm)' 1, 'Bearing 2  feature_drift  root: Bearing 3, Bearing 2' 2, "
                   "'Bearing 3  innovation_nis' 3)"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("set yrange [3.5:0.5]"), std::string::npos);
  // Bars: x centre, y (row), half width, half height, colour. Warning segment 600..1200 s: centre +900, half 300.
  EXPECT_NE(s.find("1076582859.000 2 300 "), std::string::npos);
  EXPECT_NE(s.find(" " + std::to_string(0xD00000) + "\n"), std::string::npos);  // critical segment
  EXPECT_EQ(count(s, "set label"), 0u);                                           // no text on the plot area
  EXPECT_EQ(count(s, "set arrow from graph 0"), 2u);                              // separators between channels
  const std::string none = alarm_timeline_script("shaft", {"B1"}, {}, {kT0, kT0 + 60}, PlotStyle{}, "t.png");
  EXPECT_NE(none.find("no alarms recorded"), std::string::npos);
}

TEST(ConditionTrendsScript, RobustRangeIgnoresAFewValuesFarBelowButKeepsTheMaximum) {
  ConditionSeries c;
  c.feature = "meanabs";
  c.channels = {"B1"};
  for (int i = 0; i < 200; ++i) {
    c.t.push_back(kT0 + 600.0 * i);
    c.values.resize(1);
    c.values[0].push_back(i == 199 ? 1e-4 : (i == 198 ? 2.0 : 0.1 + 0.001 * (i % 7)));
  }
  const std::string s = condition_trends_script("shaft", {c}, {}, {kT0, kT0 + 600.0 * 200}, PlotStyle{}, "x.png");
  // 1st percentile of 200 values = the 3rd smallest = 0.1; lower bound 0.1 / 1.5; upper = max 2.0 * 1.3.
  EXPECT_NE(s.find("set yrange [0.0666666667:2.6]"), std::string::npos) << s;
  EXPECT_NE(s.find("1 value(s) far below the rest not shown"), std::string::npos);
  EXPECT_NE(s.find("set ytics (0.1, 0.2, 0.5, 1, 2)\n"), std::string::npos);
}

TEST(ReportMarkdown, ListsFiguresAndFirstAlarmPerChannel) {
  std::vector<AlarmSpan> alarms{span("late", 2, Severity::Critical, kT0 + 900, std::nullopt, "Bearing 1"),
                                span("early", 2, Severity::Advisory, kT0 + 600, kT0 + 800, "Bearing|3"),
                                span("other", 1, Severity::Warning, kT0 + 700, std::nullopt, "")};
  alarms[1].max_severity = Severity::Warning;
  const std::string md = report_markdown("shaft", "/runs/x", {{"Condition trends", "condition_trends_shaft.png"}},
                                         alarms, {"a note"});
  EXPECT_NE(md.find("![Condition trends](condition_trends_shaft.png)"), std::string::npos);
  EXPECT_NE(md.find("- a note"), std::string::npos);
  EXPECT_NE(md.find("| Bearing 1 | 2004-02-12 10:42:39 | warning | feature_drift | - | still active |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| Bearing 2 | 2004-02-12 10:42:39 | advisory (escalated to warning) | feature_drift | "
                    "Bearing\\|3 | 2004-02-12 11:12:39 |"),
            std::string::npos)
      << md;
  EXPECT_EQ(count(md, "| Bearing 2 |"), 1u);  // only the first alarm of the channel
  EXPECT_NE(md.find("3 alarm(s) in total"), std::string::npos);
  EXPECT_NE(report_markdown("shaft", "/r", {}, {}, {}).find("No alarms recorded."), std::string::npos);
}
