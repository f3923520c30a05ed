// Sample-level use: one observation per factor publication carrying the mean NIS of each outcome over
// the publication's samples (OutcomeFactors.nis_mean). Healthy snapshots: NIS ~ chi-square(n)/n around a
// channel-specific model-mismatch level; failing snapshots: bearing 1's waveform carries impulsive energy
// the other channels do not explain, so its mean NIS grows several-fold while the others barely move.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "causal/alarms/alarm_engine.hpp"
#include "synthetic_group.hpp"

using namespace causal::alarms;

TEST(AlarmEngineSampleLevel, FailingSnapshotsRaiseOnBearing1WithRootCause1) {
  const int per_snapshot = 10, healthy = 3, failing = 3;
  std::mt19937_64 rng(77);
  std::gamma_distribution<double> chi(1024.0 / 2.0, 2.0 / 1024.0);  // chi-square(1024) / 1024 per publication
  std::normal_distribution<double> snap_effect(0.0, 0.05);        // snapshot-to-snapshot mismatch
  const double mismatch[4] = {1.3, 1.1, 1.2, 1.05};
  AlarmEngine e("ims2-shaft1", test::channel_names4(), {}, AlarmParams::sample_level(healthy * per_snapshot));
  std::vector<AlarmEvent> events;
  std::uint64_t idx = 0;
  for (int s = 0; s < healthy + failing; ++s) {
    double se[4];
    for (double& v : se) v = std::exp(snap_effect(rng));
    for (int q = 0; q < per_snapshot; ++q, ++idx) {
      Observation o;
      o.index = idx;
      o.time_ns = test::kT0Ns + s * test::kStepNs + q * 102400000LL;  // 2048 samples at 20 kHz
      o.mean_nis.resize(4);
      for (int k = 0; k < 4; ++k) o.mean_nis(k) = mismatch[k] * se[k] * chi(rng);
      if (s >= healthy) o.mean_nis(0) *= 4.0;  // failing: bearing 1 unexplained energy x4
      for (auto& ev : e.observe(o)) events.push_back(ev);
    }
    if (s == healthy - 1) {
      EXPECT_TRUE(e.baseline_ready());
    }
  }
  ASSERT_FALSE(events.empty());
  bool raised_b1 = false;
  for (const auto& ev : events) {
    EXPECT_EQ(ev.channel, 0) << ev.reason;
    EXPECT_GE(ev.index, static_cast<std::uint64_t>(healthy * per_snapshot));
    EXPECT_EQ(ev.root_cause_channel, 0) << ev.reason;
    raised_b1 = raised_b1 || (ev.state == AlarmState::Raised && ev.kind == kind::kInnovationRise);
  }
  EXPECT_TRUE(raised_b1);
}
