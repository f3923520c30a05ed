// One event for the alarm and the forecast: warning (2x), critical (4x) and end of life (6x) are multiples of
// the channel's healthy reference judged by one statistic, the median of the last level_window snapshots. On a
// constructed series (4 channels, one of which rises to 8x, with a single 3x spike before its warning), at
// every observation the forecast of each level says "reached" exactly when the alarm engine's level event
// reached it, the alarm's severity is warning / critical exactly when the forecast says warning / critical
// reached, and the first escalation to each level is at the first snapshot whose median of 5 crossed it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "causal/alarms/alarm_engine.hpp"
#include "causal/prognosis/alarm_prognosis.hpp"
#include "ims_variants.hpp"
#include "ims_variants_unseen.hpp"

namespace causal::prognosis {
namespace {

using alarms::AlarmEngine;
using alarms::AlarmParams;
using alarms::Observation;
using alarms::Severity;

constexpr int kRows = 620;
constexpr int kRiseStart = 300, kRiseRows = 300;  // channel 0: x8 at kRiseStart + kRiseRows
constexpr int kSpike = 330;                        // one snapshot at x3 on channel 0

// Log level of channel c at row t: N(0, 0.02^2) noise (own Box-Muller on mt19937_64) plus the rise and spike.
std::vector<std::vector<double>> series() {
  std::mt19937_64 rng(7);
  auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<std::vector<double>> y(kRows, std::vector<double>(4));
  for (int t = 0; t < kRows; ++t)
    for (int c = 0; c < 4; ++c) {
      const double z = std::sqrt(-2.0 * std::log(1.0 - uniform())) * std::cos(2.0 * M_PI * uniform());
      double v = std::log(0.05 * (1 + c)) + 0.02 * z;
      if (c == 0 && t >= kRiseStart) {
        const double tau = static_cast<double>(t - kRiseStart) / kRiseRows;
        v += std::log(8.0) * std::expm1(3.0 * tau) / std::expm1(3.0);
      }
      if (c == 0 && t == kSpike) v += std::log(3.0);
      y[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)] = v;
    }
  return y;
}

Severity open_severity(const AlarmEngine& engine, int channel) {
  Severity s = Severity::Advisory;
  for (const auto& e : engine.active_alarms())
    if (e.channel == channel && static_cast<int>(e.severity) > static_cast<int>(s)) s = e.severity;
  return s;
}

// Runs engine and trends over a table as the services feed them (a time gap the engine sees is a discontinuity
// for the trends, as in the evaluation tool) and checks at every row, for every channel's open prognoses, that the
// forecast says "reached" exactly when the engine's level event did and the alarm's severity is at that level.
// Returns the rows at which channel 0's forecast said warning / critical reached.
std::array<int, 2> check_one_event(const testing::Variant& v) {
  const auto g = static_cast<int>(v.values.cols());
  std::vector<std::string> names(v.channel_names.begin(), v.channel_names.end());
  AlarmEngine engine(v.name, names, {}, AlarmParams{});
  ChannelTrends trends(g, PrognosisParams{});
  std::array<int, 2> reached{0, 0};
  int checked = 0;
  for (Eigen::Index t = 0; t < v.values.rows(); ++t) {
    Observation obs;
    obs.index = static_cast<std::uint64_t>(t);
    obs.time_ns = v.time_ns[static_cast<std::size_t>(t)];
    obs.features = v.values.row(t).transpose();
    const auto gaps_before = engine.discontinuities();
    engine.observe(obs);
    observe_for_prognosis(trends, engine, obs, engine.discontinuities() > gaps_before);
    for (const auto& p : open_alarm_prognoses(trends, engine, obs.index)) {
      ++checked;
      EXPECT_EQ(p.time.reached, engine.level_reached(p.channel, p.ratio))
          << v.name << " row " << t << " channel " << p.channel;
      const int l = static_cast<int>(p.level);
      if (l == 2) continue;
      const Severity sev = open_severity(engine, p.channel);
      const bool alarm_at_level =
          static_cast<int>(sev) >= static_cast<int>(l == 0 ? Severity::Warning : Severity::Critical);
      EXPECT_EQ(p.time.reached, alarm_at_level) << v.name << " row " << t << " channel " << p.channel << " level " << l;
      if (p.channel == 0 && p.time.reached) ++reached[static_cast<std::size_t>(l)];
    }
  }
  EXPECT_GT(checked, 100) << v.name;
  return reached;
}

}  // namespace

// The same on the recorded IMS run to failure and three unseen variants of it (tests/support/ims_variants.hpp),
// every channel and row: a forecast never says "reached" while the alarm has not escalated to that level, and
// the alarm never escalates where the forecast says not reached. IMS bearing 1 reaches warning and critical.
TEST(AlarmLevelEvent, ImsTest2ForecastAndAlarmAgreeOnEveryRow) {
  const auto base = testing::read_base_run(std::string(CAUSAL_TWIN_DEPLOY_DIR) +
                                           "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  const auto reached = check_one_event(testing::make_unchanged_variant(base));
  EXPECT_GT(reached[0], 0) << "bearing 1 never reached warning";
  EXPECT_GT(reached[1], 0) << "bearing 1 never reached critical";
  // Unseen shapes of the same run: recording gaps with re-levels, two sensors per bearing, a re-levelled failure.
  check_one_event(testing::make_gaps_variant(base, 1));
  check_one_event(testing::make_eight_channel_variant(base, 1));
  check_one_event(testing::make_relevelled_failure_variant(base, 1));
}

TEST(AlarmLevelEvent, ForecastReachedExactlyWhenTheAlarmEscalated) {
  const AlarmParams params;  // shipped defaults
  AlarmEngine engine("g", {"b1", "b2", "b3", "b4"}, {}, params);
  ChannelTrends trends(4, PrognosisParams{});
  const auto y = series();
  const double ratios[3] = {params.warning_ratio, params.critical_ratio, PrognosisParams{}.end_of_life_ratio};
  int first_reached[3] = {-1, -1, -1}, first_severity[2] = {-1, -1}, first_median[3] = {-1, -1, -1};
  int checked = 0;
  for (int t = 0; t < kRows; ++t) {
    Observation obs;
    obs.index = static_cast<std::uint64_t>(t);
    obs.time_ns = 1'000'000'000'000'000'000LL + static_cast<std::int64_t>(t) * 600'000'000'000LL;
    obs.features.resize(4);
    for (int c = 0; c < 4; ++c) obs.features[c] = std::exp(y[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)]);
    engine.observe(obs);
    observe_for_prognosis(trends, engine, obs, false);
    if (!engine.baseline_ready()) continue;
    // The statistic, computed here from the input: median of the last 5 levels over the engine's reference.
    const double ref = engine.level_event(0).reference_log;
    std::vector<double> last;
    for (int k = std::max(0, t - params.level_window + 1); k <= t; ++k) last.push_back(y[static_cast<std::size_t>(k)][0] - ref);
    std::nth_element(last.begin(), last.begin() + static_cast<std::ptrdiff_t>(last.size() / 2), last.end());
    const double median5 = std::exp(last[last.size() / 2]);
    for (int l = 0; l < 3; ++l)
      if (first_median[l] < 0 && median5 >= ratios[l]) first_median[l] = t;
    const Severity sev = open_severity(engine, 0);
    if (first_severity[0] < 0 && sev != Severity::Advisory) first_severity[0] = t;
    if (first_severity[1] < 0 && sev == Severity::Critical) first_severity[1] = t;
    for (const auto& p : open_alarm_prognoses(trends, engine, obs.index)) {
      if (p.channel != 0) continue;
      const int l = static_cast<int>(p.level);
      ++checked;
      EXPECT_EQ(p.time.reached, engine.level_reached(0, p.ratio)) << "row " << t << " level " << l;
      if (l < 2) {
        const bool alarm_at_level = static_cast<int>(sev) >= (l == 0 ? static_cast<int>(Severity::Warning)
                                                                      : static_cast<int>(Severity::Critical));
        EXPECT_EQ(p.time.reached, alarm_at_level) << "row " << t << ": forecast and alarm disagree on " << to_string(p.level);
      }
      if (p.time.reached && first_reached[l] < 0) first_reached[l] = t;
    }
  }
  EXPECT_GT(checked, 100);
  for (int l = 0; l < 3; ++l) {
    ASSERT_GE(first_median[l], 0) << "the series never crossed level " << l;
    EXPECT_EQ(first_reached[l], first_median[l]) << "level " << l << ": forecast reached at another snapshot than the median of 5";
  }
  EXPECT_EQ(first_severity[0], first_median[0]);
  EXPECT_EQ(first_severity[1], first_median[1]);
  EXPECT_GT(first_median[0], kSpike + 5) << "the 3x spike must not count as the warning crossing";
}

}  // namespace causal::prognosis
