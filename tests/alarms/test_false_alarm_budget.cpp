// The false-alarm budget of the condition-level alarms on month-long healthy recordings, and their
// detection delay on accelerating faults, both against the robust-z reference detector
// (tests/support/robust_z_baseline.hpp). The runs are simulated (tests/support/ims_variants_month.hpp: slow
// drift, daily cycle, recording gaps with +15-20 % level steps, single-bearing operating steps of +20-40 %,
// one single-snapshot spike per day; 4 and 8 channels) and go through the services' own chain
// (causal-estimator's condition pipeline -> observation rule -> AlarmEngine, shipped parameters), so what
// is counted is what the plant would see. Truth is the construction: rows before healthy_end are healthy.
//
// FalseAlarmBudget.PrintsTables prints both tables (docs/alarm-rules.md) and asserts the bar:
//  * at most one false alarm per 20 channel-months of healthy recording, fewer channels alarmed than the
//    baseline; (BUDGET_DEBUG=1 prints every false alarm's reason);
//  * the failing bearing alarmed first, named as root cause, no later than the baseline, and at warning or
//    critical by the end of the run.
#include "ims_variants_month.hpp"
#include "robust_z_baseline.hpp"
#include "variant_series.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "causal/alarms/alarm_pipeline.hpp"

namespace causal::alarms {
namespace {

using causal::testing::MonthOptions;
using causal::testing::Variant;

constexpr double kRowsPerMonth = 30.0 * 144.0;  // 10-minute snapshots

using causal::alarms::test::failing;
using causal::alarms::test::series_of;

struct RunScore {
  int false_raises = 0;                 // product: degradation raises before healthy_end
  std::set<int> false_channels;         // product: channels with one
  int baseline_false_channels = 0;      // robust z: channels whose first alarm is before healthy_end
  std::optional<std::uint64_t> first;   // product: first raise on the failing bearing after healthy_end
  bool first_is_failing = false;        // ... and it is the first raise of any channel after healthy_end
  bool root_ok = false;                 // ... naming the failing bearing as root cause
  Severity end_severity = Severity::Advisory;  // highest severity of the failing bearing's alarms
  bool failing_alarmed = false;
  std::optional<std::size_t> baseline_first;  // robust z: first alarm on the failing bearing
  int level_steps = 0, operating_changes = 0, discontinuities = 0;
};

// healthy_range < 0: the shipped parameters; else AlarmParams::healthy_range_observations set to it.
RunScore score(const Variant& v, int healthy_range = -1) {
  auto options = causal::alarms::shipped_options(v.name);
  if (healthy_range >= 0) options.params.healthy_range_observations = healthy_range;
  const auto res = causal::alarms::run_condition_pipeline(series_of(v), options);
  RunScore s;
  std::optional<std::uint64_t> first_any;
  for (const AlarmEvent& e : res.events) {
    if (e.category != causal::alarms::category::kDegradation) {
      if (e.state != AlarmState::Raised) continue;
      const std::string k = e.kind;
      s.level_steps += k == causal::alarms::kind::kLevelStep;
      s.operating_changes += k == causal::alarms::kind::kOperatingChange;
      s.discontinuities += k == causal::alarms::kind::kDiscontinuity;
      continue;
    }
    if (failing(v, e.channel) && e.state != AlarmState::Cleared) {
      s.failing_alarmed = true;
      if (static_cast<int>(e.severity) > static_cast<int>(s.end_severity)) s.end_severity = e.severity;
    }
    if (e.state != AlarmState::Raised) continue;
    if (e.index < v.healthy_end) {
      if (std::getenv("BUDGET_DEBUG")) std::printf("FALSE %s %llu %s: %.300s\n", v.name.c_str(), static_cast<unsigned long long>(e.index), e.kind.c_str(), e.reason.c_str());
      ++s.false_raises;
      s.false_channels.insert(e.channel);
      continue;
    }
    if (!first_any) {
      first_any = e.index;
      s.first_is_failing = failing(v, e.channel);
    }
    if (failing(v, e.channel) && !s.first) {
      s.first = e.index;
      s.root_ok = failing(v, e.root_cause_channel);
    }
  }
  const auto z = causal::testing::robust_z_first_alarms(v.values);
  for (std::size_t c = 0; c < z.size(); ++c) {
    if (!z[c].first_alarm) continue;
    if (*z[c].first_alarm < v.healthy_end) {
      ++s.baseline_false_channels;
    } else if (failing(v, static_cast<int>(c)) && (!s.baseline_first || *z[c].first_alarm < *s.baseline_first)) {
      s.baseline_first = *z[c].first_alarm;
    }
  }
  return s;
}

const char* severity_name(Severity s) {
  return s == Severity::Critical ? "critical" : s == Severity::Warning ? "warning" : "advisory";
}

std::string delay(const std::optional<std::uint64_t>& at, std::size_t start) {
  if (!at) return "missed";
  char b[64];
  std::snprintf(b, sizeof b, "%lld (%.1f h)", static_cast<long long>(*at) - static_cast<long long>(start),
                (static_cast<double>(*at) - static_cast<double>(start)) / 6.0);
  return b;
}

constexpr std::uint64_t kSeeds[] = {1, 2, 3};

}  // namespace

TEST(FalseAlarmBudget, PrintsTables) {
  std::printf("\n| channels | healthy months (runs x 30 d) | product: false alarms | product: per month per channel | "
              "product: channels alarmed | baseline: channels alarmed | baseline: per month per channel (first "
              "alarms only) | level steps / operating changes / gap re-levels followed |\n|---|---|---|---|---|---|---|---|\n");
  for (int sensors : {1, 2}) {
    MonthOptions o;
    o.sensors_per_bearing = sensors;
    int raises = 0, channels_alarmed = 0, baseline_alarmed = 0, steps = 0, ops = 0, gaps = 0, g = 0;
    double months = 0.0;
    for (std::uint64_t seed : kSeeds) {
      const Variant v = causal::testing::make_month_variant(o, seed);
      const RunScore s = score(v);
      g = static_cast<int>(v.channel_names.size());
      months += static_cast<double>(v.values.rows()) / kRowsPerMonth;
      raises += s.false_raises;
      channels_alarmed += static_cast<int>(s.false_channels.size());
      baseline_alarmed += s.baseline_false_channels;
      steps += s.level_steps;
      ops += s.operating_changes;
      gaps += s.discontinuities;
    }
    std::printf("| %d | %.1f | %d | %.3f | %d of %d | %d of %d | %.3f | %d / %d / %d |\n", g, months, raises,
                raises / (months * g), channels_alarmed, g * 3, baseline_alarmed, g * 3, baseline_alarmed / (months * g),
                steps, ops, gaps);
    // The budget: at most one false alarm per 20 channel-months on these runs, and fewer channels alarmed
    // than the robust-z baseline (which alarms every channel of them).
    EXPECT_LE(raises / (months * g), 0.05) << g << " channels";
    EXPECT_LT(channels_alarmed, baseline_alarmed) << g << " channels";
  }

  std::printf("\n| run | fault: rows to +10 %% / x2 / x4 | product: delay rows (h) | product: first alarm is the failing "
              "bearing | root cause | severity at end | baseline: delay rows (h) | false alarms before onset "
              "(product / baseline channels) |\n|---|---|---|---|---|---|---|---|\n");
  for (int sensors : {1, 2}) {
    for (std::uint64_t seed : kSeeds) {
      MonthOptions o;
      o.sensors_per_bearing = sensors;
      o.fault = true;
      const Variant v = causal::testing::make_month_variant(o, seed);
      const RunScore s = score(v);
      std::printf("| %s | %.0f / %.0f / %.0f | %s | %s | %s | %s | %s | %d / %d |\n", v.name.c_str(),
                  causal::testing::fault_rows_to_ratio(o, 1.10), causal::testing::fault_rows_to_ratio(o, 2.0),
                  static_cast<double>(o.fault_rows_to_x4), delay(s.first, o.fault_start).c_str(),
                  s.first_is_failing ? "yes" : "no", s.root_ok ? "failing bearing" : "other",
                  s.failing_alarmed ? severity_name(s.end_severity) : "-",
                  delay(s.baseline_first ? std::optional<std::uint64_t>(*s.baseline_first) : std::nullopt, o.fault_start).c_str(),
                  s.false_raises, s.baseline_false_channels);
      EXPECT_EQ(s.false_raises, 0) << v.name;
      ASSERT_TRUE(s.first.has_value()) << v.name << ": the failing bearing never alarmed";
      EXPECT_TRUE(s.first_is_failing) << v.name;
      EXPECT_TRUE(s.root_ok) << v.name;
      EXPECT_NE(s.end_severity, Severity::Advisory) << v.name << ": the failing bearing never reached warning";
      if (s.baseline_first) EXPECT_LE(*s.first, *s.baseline_first) << v.name << ": later than the robust-z baseline";
    }
  }
}

// The same healthy months with more healthy movement than the alarm rules were tuned on: each bearing's own
// slow wander of +-10 % (a sinusoid of 3-8 days, MonthOptions::slow_wander) and/or 6 single short excursions of
// x1.15-1.25 for 2-4 snapshots (MonthOptions::short_excursions), against the robust-z baseline in the same
// runs. Printed as a table (docs/alarm-rules.md, section 9); asserted: with short excursions the budget of
// PrintsTables holds, and with the wander the product alarms no more channels than the baseline (a +-10 %
// wander over days crosses the +8 % floor by construction: a known limit, measured in the table).
TEST(FalseAlarmBudget, SlowWanderAndShortExcursions) {
  std::printf("\n| channels | healthy months | wander | excursions | healthy range learned over | product: false alarms | "
              "product: per month per channel | product: channels alarmed | baseline: channels alarmed | baseline: per "
              "month per channel (first alarms only) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (int sensors : {1, 2}) {
    for (const auto& [wander, range] : {std::pair{0.0, -1}, std::pair{std::log(1.10), -1}, std::pair{std::log(1.10), 432}}) {
      MonthOptions o;
      o.sensors_per_bearing = sensors;
      o.slow_wander = wander;
      o.short_excursions = 6;
      int raises = 0, channels_alarmed = 0, baseline_alarmed = 0, g = 0;
      double months = 0.0;
      for (std::uint64_t seed : kSeeds) {
        const Variant v = causal::testing::make_month_variant(o, seed);
        const RunScore s = score(v, range);
        g = static_cast<int>(v.channel_names.size());
        months += static_cast<double>(v.values.rows()) / kRowsPerMonth;
        raises += s.false_raises;
        channels_alarmed += static_cast<int>(s.false_channels.size());
        baseline_alarmed += s.baseline_false_channels;
      }
      std::printf("| %d | %.1f | %s | 6 per run | %s | %d | %.3f | %d of %d | %d of %d | %.3f |\n", g, months,
                  wander > 0.0 ? "+-10 %" : "none", range < 0 ? "warm-up + baseline + returned wander (shipped)" : "the same + 3 days (432)", raises, raises / (months * g), channels_alarmed, g * 3,
                  baseline_alarmed, g * 3, baseline_alarmed / (months * g));
      if (wander == 0.0) {
        EXPECT_LE(raises / (months * g), 0.05) << g << " channels: short excursions within the budget";
      } else {  // known limit (docs/alarm-rules.md, section 9): a +-10 % wander's first crests cross the +8 % floor
        EXPECT_LE(channels_alarmed, baseline_alarmed) << g << " channels";
        // The wander a channel came back from is learned (SignalMonitor::wander_top) and an innovation detector
        // needs innovation_persistence (4) observations at its threshold: measured 1.833 (4 channels) and 1.500
        // (8) per channel-month, from 2.667 and 1.708 with persistence 1 and 3.667 and 2.958 without the wander
        // range; the bound pins the gain.
        if (range < 0) EXPECT_LT(raises / (months * g), 2.0) << g << " channels";
      }
    }
  }
}

}  // namespace causal::alarms
