// Robustness suite: the product (causal-alarm-eval, the condition-level alarm pipeline) against the
// plain robust-z reference detector on IMS test 2 and four variants of it that the alarm tuning never saw
// (tests/support/ims_variants.hpp: gaps + level shifts, operating-change steps, 8 channels, 6000 snapshots).
//
// Truth comes from the construction of each variant: rows [0, healthy_end) are healthy (any degradation
// alarm there is false) and the failing bearing is known. Per variant the test asserts:
//  * no degradation alarm in the healthy part;
//  * the failing bearing is alarmed first after it and named as root cause of that alarm;
//  * the product is earlier than or as early as the baseline on the failing bearing and has no more false
//    alarms (channels alarmed in the healthy part).
// Events of other categories (data quality, health, operating change: a `category=` other than
// `degradation` on the event line) are reported, not counted as alarms.
//
// Every variant is asserted in its own test; RobustnessSuite.PrintsSideBySideTable prints the table for all.
#include "ims_variants.hpp"
#include "ims_variants_month.hpp"
#include "ims_variants_unseen.hpp"
#include "robust_z_baseline.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>

namespace {

using causal::testing::Variant;

constexpr std::uint64_t kSeed = 12;

struct EventLine {
  std::uint64_t index = 0;
  std::string state;     // raised, escalated, cleared, ...
  std::string severity;  // advisory, warning, critical
  std::string channel;
  std::string kind;
  std::string root_cause;
  std::string category;  // empty: the tool does not say (every alarm then is a degradation alarm)
};

// Value of `key=` in an event line: a quoted value, else up to the blank before the next "word=" token
// (channel names contain blanks).
std::string field(const std::string& line, const std::string& key) {
  const std::string tag = " " + key + "=";
  const auto at = line.find(tag);
  if (at == std::string::npos) return "";
  const std::size_t begin = at + tag.size();
  if (begin < line.size() && line[begin] == '"') return line.substr(begin + 1, line.find('"', begin + 1) - begin - 1);
  for (std::size_t from = begin;;) {
    const auto blank = line.find(' ', from);
    if (blank == std::string::npos) return line.substr(begin);
    const auto word_end = line.find(' ', blank + 1);
    const auto eq = line.find('=', blank + 1);
    if (eq != std::string::npos && eq < word_end) return line.substr(begin, blank - begin);
    from = blank + 1;
  }
}

std::vector<EventLine> parse_events(const std::string& output) {
  std::vector<EventLine> events;
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("event index=", 0) != 0) continue;
    EventLine e;
    e.index = std::stoull(field(line, "index"));
    std::istringstream words(line.substr(line.find('"', line.find("time=\"") + 6) + 1));
    words >> e.state >> e.severity;
    e.channel = field(line, "channel");
    e.kind = field(line, "kind");
    e.root_cause = field(line, "root_cause");
    e.category = field(line, "category");
    events.push_back(e);
  }
  return events;
}

struct Score {
  int false_channels = 0;                 // channels with an alarm in the healthy part
  int false_raises = 0;                   // alarm raises in the healthy part (product only)
  std::optional<std::uint64_t> first;     // first alarm on the failing bearing after the healthy part
  std::string first_channel;              // the channel alarmed first after the healthy part
  std::string root_cause;                 // named with the failing bearing's first alarm ("-" = none)
  int other_events = 0;                   // product: events of another category (operating change, ...)
  std::string end_severity = "-";         // product: highest severity of the failing bearing's alarms
};

struct Outcome {
  Variant variant;
  std::string output;  // the tool's stdout
  int exit_code = -1;
  Score product, baseline;
};

bool is_failing(const Variant& v, const std::string& channel) {
  for (int c : v.failing_channels) {
    if (v.channel_names[static_cast<std::size_t>(c)] == channel) return true;
  }
  return false;
}

Score score_product(const Variant& v, const std::vector<EventLine>& events) {
  Score s;
  std::set<std::string> false_channels;
  std::optional<std::uint64_t> first_after;
  for (const auto& e : events) {
    if (!e.category.empty() && e.category != "degradation") {
      ++s.other_events;
      continue;
    }
    if (is_failing(v, e.channel) && e.state != "cleared" &&
        (e.severity == "critical" || (e.severity == "warning" && s.end_severity != "critical") ||
         (e.severity == "advisory" && s.end_severity == "-")))
      s.end_severity = e.severity;
    if (e.state != "raised") continue;
    if (e.index < v.healthy_end) {
      false_channels.insert(e.channel);
      ++s.false_raises;
      continue;
    }
    if (!first_after || e.index < *first_after) {
      first_after = e.index;
      s.first_channel = e.channel;
    }
    if (is_failing(v, e.channel) && (!s.first || e.index < *s.first)) {
      s.first = e.index;
      s.root_cause = e.root_cause;
    }
  }
  s.false_channels = static_cast<int>(false_channels.size());
  return s;
}

Score score_baseline(const Variant& v) {
  Score s;
  const auto channels = causal::testing::robust_z_first_alarms(v.values);
  std::optional<std::size_t> first_after;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (!channels[c].first_alarm) continue;
    const std::size_t at = *channels[c].first_alarm;
    if (at < v.healthy_end) {
      ++s.false_channels;
      continue;
    }
    if (!first_after || at < *first_after) {
      first_after = at;
      s.first_channel = v.channel_names[c];
    }
    if (is_failing(v, v.channel_names[c]) && (!s.first || at < *s.first)) s.first = at;
  }
  s.root_cause = "-";  // the robust-z detector names no root cause
  return s;
}

std::string run_tool(const std::string& csv, const std::string& group, int& exit_code) {
  const std::string cmd = std::string(CAUSAL_ALARM_EVAL_BIN) + " --features '" + csv + "' --feature '' --asset-group " +
                          group + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string text;
  if (!pipe) return text;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) text.append(buf, n);
  const int status = pclose(pipe);
  exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return text;
}

const causal::testing::BaseRun& base() {
  static const auto b = causal::testing::read_base_run(std::string(CAUSAL_TWIN_DEPLOY_DIR) +
                                                       "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  return b;
}

Outcome evaluate(const Variant& v) {
  const auto dir = std::filesystem::temp_directory_path() / ("robustness_suite_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string csv = (dir / (v.name + ".csv")).string();
  causal::testing::write_variant_csv(v, csv);
  Outcome o;
  o.variant = v;
  o.output = run_tool(csv, v.name, o.exit_code);
  std::filesystem::remove_all(dir);
  o.product = score_product(v, parse_events(o.output));
  o.baseline = score_baseline(v);
  return o;
}

// The variants of make_all_variants plus 8 channels with gaps, and month-long simulated runs
// (drift, daily cycle, gaps with level steps, single-bearing steps, a spike a day) ending in an
// accelerating fault of bearing 1, with 4 and 8 channels (tests/support/ims_variants_month.hpp).
std::vector<Variant> all_variants() {
  auto all = causal::testing::make_all_variants(base(), kSeed);
  all.push_back(causal::testing::make_eight_channel_gaps_variant(base(), kSeed));
  for (int sensors : {1, 2}) {
    causal::testing::MonthOptions o;
    o.sensors_per_bearing = sensors;
    o.fault = true;
    all.push_back(causal::testing::make_month_variant(o, kSeed));
  }
  all.push_back(causal::testing::make_relevelled_failure_variant(base(), kSeed));
  all.push_back(causal::testing::make_low_baseline_stretch_variant(base()));
  return all;
}

Outcome evaluate(const std::string& name) {
  for (const auto& v : all_variants()) {
    if (v.name == name) return evaluate(v);
  }
  throw std::invalid_argument("no variant " + name);
}

std::string at(const std::optional<std::uint64_t>& i) { return i ? std::to_string(*i) : "none"; }

// The robustness bar for one variant.
void expect_holds(const Outcome& o) {
  const Variant& v = o.variant;
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_EQ(o.product.false_raises, 0) << v.name << ": degradation alarms in the healthy part (rows < " << v.healthy_end
                                       << "); " << v.description;
  ASSERT_TRUE(o.product.first.has_value()) << v.name << ": the failing bearing never alarmed";
  EXPECT_TRUE(is_failing(v, o.product.first_channel))
      << v.name << ": " << o.product.first_channel << " alarmed before the failing bearing (at " << at(o.product.first) << ")";
  EXPECT_TRUE(is_failing(v, o.product.root_cause)) << v.name << ": root cause named " << o.product.root_cause;
  EXPECT_LE(o.product.false_channels, o.baseline.false_channels) << v.name;
  if (o.baseline.first) {
    EXPECT_LE(*o.product.first, *o.baseline.first) << v.name << ": later than the robust-z baseline";
  }
  EXPECT_TRUE(o.product.end_severity == "warning" || o.product.end_severity == "critical")
      << v.name << ": the failing bearing ended at " << o.product.end_severity;
}

}  // namespace

TEST(RobustnessSuite, PrintsSideBySideTable) {
  std::printf("\n| variant | rows x channels | healthy rows | product: false alarms | product: first alarm on the failing "
              "bearing | product: root cause | product: severity at end | product: other events | baseline: false "
              "alarms | baseline: first alarm on the failing bearing | baseline: first channel |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& v : all_variants()) {
    const Outcome o = evaluate(v);
    ASSERT_EQ(o.exit_code, 0) << v.name << ":\n" << o.output;
    std::printf("| %s | %lld x %lld | %zu | %d (%d raises) | %s | %s | %s | %d | %d | %s | %s |\n", v.name.c_str(),
                static_cast<long long>(v.values.rows()), static_cast<long long>(v.values.cols()), v.healthy_end,
                o.product.false_channels, o.product.false_raises, at(o.product.first).c_str(),
                o.product.root_cause.empty() ? "-" : o.product.root_cause.c_str(), o.product.end_severity.c_str(),
                o.product.other_events,
                o.baseline.false_channels, at(o.baseline.first).c_str(),
                o.baseline.first_channel.empty() ? "-" : o.baseline.first_channel.c_str());
  }
  std::printf("(variants: seed %llu; %s)\n", static_cast<unsigned long long>(kSeed),
              "rows < healthy rows are healthy; false alarms = channels alarmed there");
}

// The parser reads what the tool prints (a line of today's format, and one with a category field).
TEST(RobustnessSuite, ParsesEventLines) {
  const auto events = parse_events(
      "event index=533 time=\"2004-02-16 03:22:39 UTC\" raised    advisory id=g/1/feature_drift/1 channel=Bearing 1 C1 "
      "kind=feature_drift score=4.539 threshold=3.941 root_cause=Bearing 1 C2\n"
      "noise outcome 1: q=1\n"
      "event index=7 time=\"x\" raised warning id=g/2/op/1 channel=Bearing 2 kind=operating_change score=1 threshold=1 "
      "root_cause=Bearing 2 category=operating_change confidence=0.8\n");
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].index, 533u);
  EXPECT_EQ(events[0].state, "raised");
  EXPECT_EQ(events[0].channel, "Bearing 1 C1");
  EXPECT_EQ(events[0].kind, "feature_drift");
  EXPECT_EQ(events[0].root_cause, "Bearing 1 C2");
  EXPECT_EQ(events[0].category, "");
  EXPECT_EQ(events[1].root_cause, "Bearing 2");
  EXPECT_EQ(events[1].category, "operating_change");
}

// Variants the product handles today.
TEST(RobustnessSuite, UnchangedTestTwo) { expect_holds(evaluate("unchanged")); }
TEST(RobustnessSuite, EightChannels) { expect_holds(evaluate("eight_channels")); }
TEST(RobustnessSuite, StretchedTo6000) { expect_holds(evaluate("stretched")); }

// Time gaps with level shifts and operating-change steps (the engine re-baselines
// across them and reports operating_change events). Before the engine's work (main f4e471e): gaps -> every
// channel alarmed at the first gap (row 157) with root cause Bearing 2; steps -> the stepped channels alarmed
// at once (Bearing 4 at 199, Bearing 2 at 351) and bearing 1's alarm at 533 named Bearing 4.
TEST(RobustnessSuite, TimeGapsWithLevelShifts) { expect_holds(evaluate("gaps")); }
TEST(RobustnessSuite, OperatingChangeSteps) { expect_holds(evaluate("steps")); }

// 8 channels (two sensors per bearing) with the gaps and level steps of TimeGapsWithLevelShifts,
// and month-long simulated runs with an accelerating fault at the end.
TEST(RobustnessSuite, EightChannelsWithGaps) { expect_holds(evaluate("eight_channels_gaps")); }
TEST(RobustnessSuite, MonthLongFourChannels) { expect_holds(evaluate("month_fault_4ch_s12")); }
TEST(RobustnessSuite, MonthLongEightChannels) { expect_holds(evaluate("month_fault_8ch_s12")); }

// Two runs the rules were not tuned on (tests/support/ims_variants_unseen.hpp; asserted in detail by
// alarms_unseen_runs): a failure after a re-levelling gap, and a baseline learned in a low stretch.
TEST(RobustnessSuite, RelevelledFailure) { expect_holds(evaluate("relevelled_failure")); }
TEST(RobustnessSuite, LowBaselineStretch) { expect_holds(evaluate("low_baseline_stretch")); }
