// The verdict (tools/causal_report/verdict.cpp): status from the degradation alarms still open at the end,
// events of other categories counted beside it, first alarm, root cause of the worst open alarm, top
// recommendation (reliable first), against hand-built alarm histories.
#include "verdict.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace causal::report;

namespace {

AlarmRecord row(const std::string& id, const std::string& state, Severity sev, double t, const std::string& category,
                const std::string& channel, const std::string& root, double index) {
  AlarmRecord r;
  r.alarm_id = id;
  r.state = state;
  r.severity = sev;
  r.kind = "feature_drift";
  r.category = category;
  r.channel_name = channel;
  r.root_cause_name = root;
  r.time = t;
  r.raised = t;
  r.raised_utc = "t" + std::to_string(static_cast<int>(t));
  r.sample_index = index;
  return r;
}

RecommendationRecord rec(int rank, bool reliable, const std::string& text) {
  RecommendationRecord r;
  r.rank = rank;
  r.reliable = reliable;
  r.text = text;
  return r;
}

TEST(Verdict, WorstOpenDegradationAlarmDecidesAndOtherCategoriesAreCountedBeside) {
  const std::vector<AlarmRecord> alarms{
      row("g/3/operating_change/1", "raised", Severity::Advisory, 50, "operating_change", "B3", "", 5),
      row("g/1/feature_drift/1", "raised", Severity::Advisory, 100, "degradation", "B1", "B1", 10),
      row("g/2/feature_drift/1", "raised", Severity::Advisory, 200, "degradation", "B2", "B1", 20),
      row("g/1/feature_drift/1", "escalated", Severity::Critical, 300, "degradation", "B1", "B4", 30),
      row("g/2/feature_drift/1", "cleared", Severity::Advisory, 400, "degradation", "B2", "B1", 40),
      row("g/1/data_quality/1", "raised", Severity::Warning, 450, "data_quality", "B1", "", 45)};
  AlarmRecord confident = alarms[3];
  const AssetVerdict v = verdict_of("g", alarms, {rec(1, false, "No reliable lever"), rec(2, true, "rank two"),
                                                  rec(1, true, "Reduce B4 by 10 %"), rec(1, false, "later, unreliable")});
  EXPECT_EQ(v.status, "CRITICAL");
  EXPECT_EQ(v.first_alarm, "t100 B1 feature_drift (index 10)");  // the operating change at t50 is not a fault
  EXPECT_EQ(v.root_cause, "B4");                           // re-evaluated on the escalation row
  EXPECT_EQ(v.top_recommendation, "Reduce B4 by 10 %");    // the latest reliable rank-1 advice
  EXPECT_EQ(v.events, "1 data quality event, 1 operating change event");
  const std::string table = verdict_table({v});
  EXPECT_NE(table.find("g            CRITICAL"), std::string::npos) << table;
  EXPECT_NE(table.find("  advice: Reduce B4 by 10 %\n"), std::string::npos);
}

TEST(Verdict, RecoveredHealthyAndUnreliableAdvice) {
  const std::vector<AlarmRecord> cleared{row("g/1/x/1", "raised", Severity::Warning, 10, "degradation", "B1", "B1", 1),
                                         row("g/1/x/1", "cleared", Severity::Warning, 20, "degradation", "B1", "B1", 2)};
  const AssetVerdict r = verdict_of("g", cleared, {rec(1, false, "No reliable lever: the interval includes zero")});
  EXPECT_EQ(r.status, "recovered");
  EXPECT_EQ(r.root_cause, "-");
  EXPECT_EQ(r.top_recommendation, "No reliable lever: the interval includes zero");
  const AssetVerdict h =
      verdict_of("g", {row("g/2/oc/1", "raised", Severity::Advisory, 5, "operating_change", "B2", "", 1)}, {});
  EXPECT_EQ(h.status, "healthy");
  EXPECT_EQ(h.first_alarm, "-");
  EXPECT_EQ(h.top_recommendation, "-");
}

TEST(Verdict, ShowsTheLatestAlarmEventsActionAtItsIndex) {
  const std::vector<AlarmRecord> alarms{row("g/1/x/1", "raised", Severity::Advisory, 10, "degradation", "B1", "B1", 533),
                                        row("g/1/x/1", "escalated", Severity::Critical, 20, "degradation", "B1", "B1", 980)};
  RecommendationRecord first = rec(1, false, "text 1"), later = rec(1, false, "text 2");
  first.action = "Act on B1 (advisory alarm): inspect it.";
  first.sample_index = "533";
  later.action = "Act on B1 (critical alarm): replace it at the earliest safe stop.";
  later.sample_index = "980";
  // The latest event's action wins over an older reliable lever without an action column.
  const AssetVerdict v = verdict_of("g", alarms, {rec(1, true, "Reduce B4 by 10 %"), first, later});
  EXPECT_EQ(v.top_recommendation, "at 980: Act on B1 (critical alarm): replace it at the earliest safe stop.");
}

}  // namespace

namespace {

PrognosisRecord prog(const std::string& channel, double index, const std::string& level, bool reached,
                     const std::string& text) {
  PrognosisRecord p;
  p.asset_group = "g";
  p.channel_name = channel;
  p.sample_index = index;
  p.level = level;
  p.known = true;
  p.reached = reached;
  p.text = text;
  return p;
}

}  // namespace

TEST(Verdict, PrognosisOfTheRootCausesNextLevelFromItsLatestSnapshot) {
  const std::vector<AlarmRecord> alarms{
      row("g/2/feature_drift/1", "raised", Severity::Warning, 100, "degradation", "B2", "B1", 10)};
  const std::vector<PrognosisRecord> prognoses{
      prog("B1", 9, "warning", false, "B1 old"), prog("B1", 10, "warning", true, "B1 has reached warning"),
      prog("B1", 10, "critical", false, "B1 reaches critical in 1.0 h"), prog("B2", 10, "critical", false, "B2 x")};
  const AssetVerdict v = verdict_of("g", alarms, {}, prognoses);
  EXPECT_EQ(v.prognosis, "B1 reaches critical in 1.0 h");  // the root cause, its next level above WARNING
  EXPECT_NE(verdict_table({v}).find("  prognosis: B1 reaches critical in 1.0 h\n"), std::string::npos);
  // Root cause without prognoses: the alarmed channel's; a healthy asset: none.
  EXPECT_EQ(verdict_of("g", alarms, {}, {prognoses[3]}).prognosis, "B2 x");
  EXPECT_EQ(verdict_of("g", {}, {}, prognoses).prognosis, "");
  // An open ADVISORY looks at warning: reached already, so critical.
  std::vector<AlarmRecord> advisory = alarms;
  advisory[0].severity = Severity::Advisory;
  EXPECT_EQ(verdict_of("g", advisory, {}, prognoses).prognosis, "B1 reaches critical in 1.0 h");
  // A CRITICAL looks at end_of_life: none recorded for B1 or B2, so nothing.
  std::vector<AlarmRecord> critical = alarms;
  critical[0].severity = Severity::Critical;
  EXPECT_EQ(verdict_of("g", critical, {}, prognoses).prognosis, "");
}

// A low root-cause confidence is explained under the verdict line with the rival the alarm's reason names
// (common/alarms/src/alarm_explain.cpp); a confident one adds nothing.
TEST(Verdict, LowRootCauseConfidenceShowsItsRival) {
  AlarmRecord low = row("g/2/feature_drift/1", "escalated", Severity::Critical, 9, "degradation", "B1 C2", "B1 C2", 970);
  low.root_cause_confidence = 0.0;
  low.reason = "Escalated to critical. Root cause: B1 C2 itself. Attribution confidence 0.00: B1 C5, whose trouble "
               "began no later, shows more own-change evidence now (z = 5.1 against -0.1): the root may be either. "
               "Factors that moved: x2_1.";
  const AssetVerdict v = verdict_of("g", {low}, {});
  EXPECT_EQ(v.root_cause, "B1 C2 (confidence 0.00)");
  EXPECT_EQ(v.root_cause_note, "Attribution confidence 0.00: B1 C5, whose trouble began no later, shows more "
                               "own-change evidence now (z = 5.1 against -0.1)");
  EXPECT_NE(verdict_table({v}).find("  root cause: Attribution confidence 0.00: B1 C5"), std::string::npos);
  AlarmRecord sure = low;
  sure.root_cause_confidence = 1.0;
  sure.reason = "Escalated to critical. Root cause: B1 C2 itself.";
  EXPECT_EQ(verdict_of("g", {sure}, {}).root_cause_note, "");
  EXPECT_EQ(verdict_table({verdict_of("g", {sure}, {})}).find("root cause:"), std::string::npos);
}
