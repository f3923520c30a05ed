// causal::pipeline::InputScreen and its use by AssetPipeline: one bad value, one broken channel or one broken
// asset group never throws, never puts a NaN in a report and never disturbs another asset group.
//
// Data: a 4-channel structural VAR with constant, known coefficients (tests/analysis/svar_sim.hpp, its own
// simulator), so "tracking the true factors" is checked against the truth, not against this code. Faults go
// into ONE channel (channel 3, 0-based 2) from row kStart for kLength rows. Expected events and counters are
// derived by hand from the screen's documented rules (input_screen.hpp) and the injected data.
//
// What is identical and what only close. The filter uses a sample only when ALL channels are finite (its
// documented contract), so every row the screen turns into NaN is skipped by every outcome of that group:
//  * every report before the first faulty row is bitwise identical to the clean run's;
//  * afterwards every outcome's factors stay within a few of their standard deviations of the clean run's
//    (kSingleValueSd, kChannelFaultSd) and within kTruthSd of the true coefficients at the end of the run
//    (after the channel recovered);
//  * another asset group fed in the same process is bitwise identical to its run alone.
#include "causal/pipeline/asset_pipeline.hpp"
#include "causal/pipeline/input_screen.hpp"

#include "../analysis/svar_sim.hpp"
#include "same_fields.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace causal::pipeline {
namespace {

namespace sim = causal::analysis::test;

constexpr int kG = 4;
constexpr int kBad = 2;                    // the faulty channel (0-based)
constexpr Eigen::Index kRows = 24576;
constexpr Eigen::Index kStart = 8192;      // first faulty row (a multiple of the 1024-value scale block)
constexpr Eigen::Index kLength = 4096;     // faulty rows
constexpr Eigen::Index kEnd = kStart + kLength;
constexpr Eigen::Index kFrame = 512;
// Tolerances in units of each factor's reported standard deviation (about 0.03 here). One rejected row moves
// the factors by 0.03 sd (measured); a channel quarantined for 8000 rows (fault + recovery) costs the group
// those rows (every outcome skips them) plus the values passed before detection: up to 2.7 sd (measured).
// The clean run itself ends 1.3 sd from the truth.
constexpr double kSingleValueSd = 0.1;
constexpr double kChannelFaultSd = 3.5;
constexpr double kTruthSd = 3.0;
const InputScreenParams kScreen = InputScreenParams::for_samples();

enum class Fault { Huge, NaN, PosInf, Dead, Tiny, Exploded };

struct Data {
  sim::TrueSvar truth;
  RowMajorMatrix y;
};

Data simulate(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Data d;
  d.truth = sim::random_svar(rng, kG, 1);
  const Eigen::MatrixXd e =
      sim::draw_noise(rng, static_cast<int>(kRows), Eigen::VectorXd::Ones(kG), sim::NoiseKind::uniform);
  d.y = sim::simulate(d.truth, e);
  return d;
}

RowMajorMatrix inject(RowMajorMatrix y, Fault f) {
  auto col = y.col(kBad);
  switch (f) {
    case Fault::Huge: col[kStart] = 1e300; break;
    case Fault::NaN: col[kStart] = std::numeric_limits<double>::quiet_NaN(); break;
    case Fault::PosInf: col[kStart] = std::numeric_limits<double>::infinity(); break;
    case Fault::Dead: col.segment(kStart, kLength).setZero(); break;
    case Fault::Tiny: col.segment(kStart, kLength) *= 1e-9; break;
    case Fault::Exploded: col.segment(kStart, kLength) *= 1e6; break;
  }
  return y;
}

// Sample level only, automatic noise (the path that threw on main), the true causal order configured.
AssetPipelineParams params_for(const sim::TrueSvar& truth, bool condition_level = false) {
  AssetPipelineParams p;
  p.sample.model.lag_order = 1;
  p.sample.model.include_self_lags = true;
  std::vector<int> position(kG);
  for (int i = 0; i < kG; ++i) position[static_cast<std::size_t>(truth.order[static_cast<std::size_t>(i)])] = i;
  p.sample.model.instantaneous_allowed.assign(kG, std::vector<bool>(kG, false));
  for (int k = 0; k < kG; ++k)
    for (int j = 0; j < kG; ++j) p.sample.model.instantaneous_allowed[k][j] = position[j] < position[k];
  p.sample.noise.automatic = true;
  p.sample.noise.fixed = estimation::NoiseParams{1e-6, 1.0, 1.0};
  p.sample.noise.calibration_samples = 2048;
  p.sample.publish_every = 256;
  p.condition_level = condition_level;
  p.condition.min_samples = 256;
  p.condition_model.model.lag_order = 1;
  p.condition_model.model.include_self_lags = true;
  p.condition_model.noise.fixed = estimation::NoiseParams{1e-4, 1e-2, 1.0};
  p.condition_model.publish_every = 1;
  return p;
}

// Frames of kFrame rows; with the condition level every 4096 rows form one segment (snapshot).
void feed(AssetPipeline& pipe, const RowMajorMatrix& y, Eigen::Index frame, PipelineOutput& out) {
  const Eigen::Index rows = std::min(kFrame, y.rows() - frame * kFrame);
  const Eigen::Index first = frame * kFrame;
  const bool end = (first + rows) % 4096 == 0;
  const auto check = pipe.feed_frame(y.middleRows(first, rows), static_cast<std::uint64_t>(first),
                                     static_cast<std::uint64_t>(first / 4096), frame == 0, end, false,
                                     1'000'000'000LL * first, 20'000.0, out);
  ASSERT_TRUE(check.ok) << check.problem;
}

struct PipelineRun {
  std::unique_ptr<AssetPipeline> pipe;  // kept for its counters and layout
  PipelineOutput out;
};

PipelineRun run(const AssetPipelineParams& p, const RowMajorMatrix& y) {
  PipelineRun r{std::make_unique<AssetPipeline>(p), {}};
  for (Eigen::Index f = 0; f * kFrame < y.rows(); ++f) feed(*r.pipe, y, f, r.out);
  r.pipe->finish(r.out);
  return r;
}

Eigen::VectorXd true_factors(const AssetPipeline& pipe, const sim::TrueSvar& truth, int k) {
  const auto& regs = pipe.sample_stream()->layout().regressors(k);
  Eigen::VectorXd x(static_cast<Eigen::Index>(regs.size()));
  for (std::size_t i = 0; i < regs.size(); ++i) {
    const int j = regs[i].channel;
    x[static_cast<Eigen::Index>(i)] = regs[i].lag == 0 ? truth.a0(k, j) : truth.lags[0](k, j);
  }
  return x;
}

bool bitwise_equal(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

// No NaN in any report: factors and standard deviations always finite and positive, innovation statistics
// finite whenever the interval had updates (an interval without updates reports count 0 and NaN means).
void expect_clean_reports(const std::vector<FactorReport>& reports) {
  for (const FactorReport& r : reports) {
    ASSERT_TRUE(r.factors.allFinite()) << "outcome " << r.outcome << " at " << r.sample_index;
    ASSERT_TRUE(r.std_devs.allFinite()) << "outcome " << r.outcome << " at " << r.sample_index;
    ASSERT_EQ(r.degenerate_std, 0u) << "outcome " << r.outcome << " at " << r.sample_index;
    if (r.innovation_count > 0) {
      ASSERT_TRUE(std::isfinite(r.innovation_mean) && std::isfinite(r.nis_mean)) << r.sample_index;
    }
    ASSERT_TRUE(std::isfinite(r.q) && std::isfinite(r.r) && r.r > 0.0);
  }
}

struct Expected {
  std::vector<std::pair<QualityEventKind, std::uint64_t>> events;  // kind, index
  ChannelQualityCounters counters;
};

// Hand-derived from the rules in input_screen.hpp (blocks of 1024 values aligned with kStart and kEnd).
Expected expected_for(Fault f, const RowMajorMatrix& bad, const RowMajorMatrix& clean) {
  Expected e;
  auto& c = e.counters;
  c.screened = kRows;
  const std::uint64_t s = kStart, end = kEnd, recover = kEnd + kScreen.recovery_samples - 1;
  switch (f) {
    case Fault::Huge:
      e.events = {{QualityEventKind::OutOfRange, s}};
      c.out_of_range = 1;
      break;
    case Fault::NaN:
    case Fault::PosInf:
      e.events = {{QualityEventKind::NonFinite, s}};
      c.non_finite = 1;
      break;
    case Fault::Dead:  // sudden_run equal zeros: stuck; the last all-zero block ends at kEnd - 1
      e.events = {{QualityEventKind::Stuck, s + kScreen.sudden_run - 1}, {QualityEventKind::Recovered, recover}};
      c.stuck = 1;
      c.recovered = 1;
      c.quarantined_values = recover - (s + kScreen.sudden_run - 1);
      break;
    case Fault::Tiny:  // sudden_run values below 1e-3 x reference (|y| < 1e3 for every scaled value)
      e.events = {{QualityEventKind::ScaleChange, s + kScreen.sudden_run - 1}, {QualityEventKind::Recovered, recover}};
      c.scale_change = 1;
      c.recovered = 1;
      c.quarantined_values = recover - (s + kScreen.sudden_run - 1);
      break;
    case Fault::Exploded: {
      // Reference: median |x| of the channel's first block (clean data), computed here independently.
      std::vector<double> block(kScreen.scale_window);
      for (std::size_t i = 0; i < block.size(); ++i) block[i] = std::abs(clean(static_cast<Eigen::Index>(i), kBad));
      std::sort(block.begin(), block.end());
      const double ref = 0.5 * (block[block.size() / 2 - 1] + block[block.size() / 2]);
      std::size_t run = 0;
      bool quarantined = false, last_high = false;
      for (std::uint64_t i = s; i < end; ++i) {
        const double x = bad(static_cast<Eigen::Index>(i), kBad);
        const bool high = std::abs(x) > kScreen.max_abs_value || std::abs(x) > kScreen.scale_explosion * ref;
        if (high) {
          ++c.out_of_range;
          if (!last_high) e.events.push_back({QualityEventKind::OutOfRange, i});
          if (++run >= kScreen.sudden_run && !quarantined) {
            quarantined = true;
            e.events.push_back({QualityEventKind::ScaleChange, i});
          }
        } else {
          run = 0;
          if (quarantined) ++c.quarantined_values;
        }
        last_high = high;
      }
      c.quarantined_values += recover - end;  // the clean rows before recovery
      c.scale_change = 1;
      c.recovered = 1;
      e.events.push_back({QualityEventKind::Recovered, recover});
      break;
    }
  }
  return e;
}

class FaultInOneChannel : public ::testing::TestWithParam<Fault> {};

TEST_P(FaultInOneChannel, ScreenedExactlyAndEveryOutcomeKeepsTracking) {
  const Data d = simulate(20261123);
  const RowMajorMatrix bad = inject(d.y, GetParam());
  const AssetPipelineParams p = params_for(d.truth);
  const PipelineOutput clean = run(p, d.y).out;
  PipelineRun faulty;
  ASSERT_NO_THROW(faulty = run(p, bad));
  const PipelineOutput& out = faulty.out;
  const AssetPipeline* bad_pipe = faulty.pipe.get();

  // Events and counters: exact.
  const Expected want = expected_for(GetParam(), bad, d.y);
  ASSERT_EQ(out.quality_events.size(), want.events.size());
  for (std::size_t i = 0; i < want.events.size(); ++i) {
    const QualityEvent& ev = out.quality_events[i];
    SCOPED_TRACE(ev.reason);
    EXPECT_EQ(ev.channel, kBad);
    EXPECT_EQ(ev.level, ScreenLevel::Sample);
    EXPECT_EQ(ev.kind, want.events[i].first);
    EXPECT_EQ(ev.index, want.events[i].second);
    EXPECT_FALSE(ev.reason.empty());
  }
  const auto& counters = bad_pipe->quality_counters();
  ASSERT_EQ(counters.size(), static_cast<std::size_t>(kG));
  for (int j = 0; j < kG; ++j) {
    const ChannelQualityCounters& got = counters[static_cast<std::size_t>(j)];
    ChannelQualityCounters w;
    w.screened = static_cast<std::uint64_t>(kRows);
    if (j == kBad) w = want.counters;
    SCOPED_TRACE("channel " + std::to_string(j));
    EXPECT_SAME_FIELDS(got, w, screened, non_finite, out_of_range, quarantined_values, stuck, scale_change, recovered);
    EXPECT_FALSE(got.quarantined);
  }
  EXPECT_TRUE(clean.quality_events.empty());

  // Reports: none with a NaN; same count and cadence as the clean run.
  expect_clean_reports(out.sample_reports);
  expect_clean_reports(clean.sample_reports);
  ASSERT_EQ(out.sample_reports.size(), clean.sample_reports.size());
  EXPECT_TRUE(bad_pipe->sample_stream()->warnings().empty());  // the calibration window was clean
  // Differences in units of the clean run's reported standard deviation of each factor.
  const bool single_value = GetParam() == Fault::Huge || GetParam() == Fault::NaN || GetParam() == Fault::PosInf;
  const double close_sd = single_value ? kSingleValueSd : kChannelFaultSd;
  double worst = 0.0;
  for (std::size_t i = 0; i < out.sample_reports.size(); ++i) {
    const FactorReport& a = out.sample_reports[i];
    const FactorReport& b = clean.sample_reports[i];
    ASSERT_EQ(a.sample_index, b.sample_index);
    ASSERT_EQ(a.outcome, b.outcome);
    if (a.sample_index < static_cast<std::uint64_t>(kStart)) {
      ASSERT_TRUE(bitwise_equal(a.factors, b.factors)) << a.sample_index;
      ASSERT_TRUE(bitwise_equal(a.std_devs, b.std_devs)) << a.sample_index;
    } else {
      worst = std::max(worst, ((a.factors - b.factors).array() / b.std_devs.array()).abs().maxCoeff());
    }
  }
  EXPECT_LE(worst, close_sd) << "largest factor difference to the clean run after the fault, in sd";
  // Every outcome tracks the truth at the end, the faulty channel's own outcome included.
  for (int k = 0; k < kG; ++k) {
    const FactorReport& last = out.sample_reports[out.sample_reports.size() - kG + static_cast<std::size_t>(k)];
    ASSERT_EQ(last.outcome, k);
    const Eigen::VectorXd truth = true_factors(*bad_pipe, d.truth, k);
    const double off = ((last.factors - truth).array() / last.std_devs.array()).abs().maxCoeff();
    EXPECT_LE(off, kTruthSd) << "outcome " << k + 1;
  }
}

std::string fault_name(const ::testing::TestParamInfo<Fault>& info) {
  static const char* const kNames[] = {"Huge1e300", "NaN", "PosInf", "DeadChannel", "Scaled1e_9", "Scaled1e6"};
  return kNames[static_cast<int>(info.param)];
}

INSTANTIATE_TEST_SUITE_P(Faults, FaultInOneChannel,
                         ::testing::Values(Fault::Huge, Fault::NaN, Fault::PosInf, Fault::Dead, Fault::Tiny,
                                           Fault::Exploded),
                         fault_name);

// Two asset groups in one process, frames interleaved: the good one's output is bitwise what it is alone.
TEST(InputScreenIsolation, ABrokenAssetGroupNeverChangesAnotherOne) {
  const Data good = simulate(11), broken = simulate(12);
  RowMajorMatrix worst = inject(inject(broken.y, Fault::Exploded), Fault::Huge);
  worst.col(0).segment(100, 3000).setZero();       // dead inside the calibration windows
  worst(5, 1) = std::numeric_limits<double>::quiet_NaN();
  const PipelineOutput alone = run(params_for(good.truth, true), good.y).out;
  AssetPipeline a(params_for(good.truth, true)), b(params_for(broken.truth, true));
  PipelineOutput out_a, out_b;
  for (Eigen::Index f = 0; f * kFrame < kRows; ++f) {
    feed(b, worst, f, out_b);
    feed(a, good.y, f, out_a);
  }
  b.finish(out_b);
  a.finish(out_a);
  EXPECT_FALSE(out_b.quality_events.empty());
  EXPECT_TRUE(out_a.quality_events.empty());
  ASSERT_EQ(out_a.sample_reports.size(), alone.sample_reports.size());
  ASSERT_EQ(out_a.condition_reports.size(), alone.condition_reports.size());
  ASSERT_EQ(out_a.conditions.size(), alone.conditions.size());
  for (std::size_t i = 0; i < alone.sample_reports.size(); ++i) {
    ASSERT_TRUE(bitwise_equal(out_a.sample_reports[i].factors, alone.sample_reports[i].factors)) << i;
    ASSERT_TRUE(bitwise_equal(out_a.sample_reports[i].std_devs, alone.sample_reports[i].std_devs)) << i;
  }
  for (std::size_t i = 0; i < alone.condition_reports.size(); ++i) {
    ASSERT_TRUE(bitwise_equal(out_a.condition_reports[i].factors, alone.condition_reports[i].factors)) << i;
  }
  for (std::size_t i = 0; i < alone.conditions.size(); ++i) {
    ASSERT_TRUE(bitwise_equal(out_a.conditions[i].values, alone.conditions[i].values)) << i;
  }
  expect_clean_reports(out_b.sample_reports);
}

// Ready-made condition vectors get their own screen (for_conditions()): one absurd value in channel 2 is one
// out-of-range event and one rejected vector; channel 3 frozen from vector 24 on is stuck at its 10th equal
// value (vector 33) and quarantined to the end; the condition reports keep their cadence and hold no NaN.
TEST(InputScreenConditions, ReadyMadeVectorsAreScreenedPerChannel) {
  AssetPipelineParams p;
  p.sample_level = false;
  p.condition_model.model.lag_order = 1;
  p.condition_model.model.include_self_lags = true;
  p.condition_model.noise.fixed = estimation::NoiseParams{1e-4, 1e-2, 1.0};
  p.condition_model.publish_every = 1;
  AssetPipeline pipe(p);
  PipelineOutput out;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> level(0.05, 0.08);
  Eigen::VectorXd frozen(kG);
  for (int i = 0; i < 40; ++i) {
    Eigen::VectorXd v(kG);
    for (int j = 0; j < kG; ++j) v[j] = level(rng);
    if (i == 20) v[1] = 1e300;
    if (i == 24) frozen = v;
    if (i >= 24) v[2] = frozen[2];
    ASSERT_TRUE(pipe.feed_condition(v, static_cast<std::uint64_t>(i), i == 0, 1000LL * i, out).ok);
  }
  pipe.finish(out);
  ASSERT_EQ(out.quality_events.size(), 2u);
  EXPECT_EQ(out.quality_events[0].level, ScreenLevel::Condition);
  EXPECT_EQ(out.quality_events[0].kind, QualityEventKind::OutOfRange);
  EXPECT_EQ(out.quality_events[0].channel, 1);
  EXPECT_EQ(out.quality_events[0].index, 20u);
  EXPECT_EQ(out.quality_events[1].kind, QualityEventKind::Stuck);
  EXPECT_EQ(out.quality_events[1].channel, 2);
  EXPECT_EQ(out.quality_events[1].index, 33u);
  const auto& c = pipe.quality_counters(ScreenLevel::Condition);
  ASSERT_EQ(c.size(), static_cast<std::size_t>(kG));
  EXPECT_EQ(c[1].out_of_range, 1u);
  EXPECT_EQ(c[2].stuck, 1u);
  EXPECT_EQ(c[2].quarantined_values, 7u);  // vectors 33..39
  EXPECT_TRUE(c[2].quarantined);
  for (const auto& frame_counters : pipe.quality_counters(ScreenLevel::Sample)) {
    EXPECT_EQ(frame_counters.screened, 0u);  // no frame was fed
  }
  ASSERT_EQ(out.condition_reports.size(), 40u * kG);
  expect_clean_reports(out.condition_reports);
  // Rejected vectors: 20 and 33..39, counted by the filter.
  EXPECT_EQ(out.condition_reports.back().rejected, 8u);
}

// The scale verdict on one block after a reference block of ones, against the median computed by hand:
// quarantined (a scale_change event) iff median / 1 < collapse (0.5). Even blocks whose middle pair straddles
// the limit are the cases the screen cannot settle by counting alone.
bool block_quarantines(const std::vector<double>& block) {
  InputScreenParams p;
  p.scale_window = block.size();
  p.recovery_samples = block.size();
  p.stuck_samples = 0;
  p.sudden_run = 0;
  p.scale_collapse = 0.5;
  p.scale_explosion = 4.0;
  InputScreen screen(p, 1, ScreenLevel::Sample);
  std::vector<double> rows(block.size(), 1.0);  // the reference block: median 1
  rows.insert(rows.end(), block.begin(), block.end());
  std::vector<QualityEvent> events;
  screen.screen(rows.data(), rows.size(), events);
  return screen.counters()[0].scale_change == 1 && screen.counters()[0].quarantined;
}

TEST(InputScreenScaleBlock, VerdictEqualsTheMedianTestIncludingStraddlingMiddlePairs) {
  EXPECT_FALSE(block_quarantines({0.2, 0.3, 0.9, 1.0}));   // median 0.6 (pair straddles 0.5)
  EXPECT_TRUE(block_quarantines({0.2, 0.3, 0.5, 1.0}));    // median 0.4 (pair 0.3 | 0.5 straddles)
  EXPECT_TRUE(block_quarantines({0.2, 0.3, 0.4, 1.0}));    // median 0.35
  EXPECT_FALSE(block_quarantines({0.3, 0.7, 0.4, 0.9}));   // median 0.55 (pair 0.4 | 0.7), unsorted
  EXPECT_TRUE(block_quarantines({0.6, 0.1, 0.2, 0.3}));    // median 0.25
  EXPECT_FALSE(block_quarantines({0.9, 1.0, 1.1, 3.9}));   // median 1.05
  EXPECT_TRUE(block_quarantines({0.1, 0.2, 0.4, 3.0, 3.0}));   // odd: median 0.4
  EXPECT_FALSE(block_quarantines({0.1, 0.2, 0.5, 3.0, 3.0}));  // odd: median 0.5, not below 0.5
  EXPECT_FALSE(block_quarantines({0.1, 0.2, 0.6, 3.0, 3.0}));  // odd: median 0.6
}

// The scale verdict at the limits themselves: a block of three values v after a reference block of r quarantines
// exactly when fl(v / r) < collapse or fl(v / r) > explosion, for v one double step at a time around collapse x r and
// explosion x r (the screen counts against exact bounds instead of dividing; one step off would show here).
bool quarantined_at(double reference, double v) {
  InputScreenParams p;
  p.scale_window = 3;
  p.recovery_samples = 3;
  p.stuck_samples = 0;
  p.sudden_run = 0;
  InputScreen screen(p, 1, ScreenLevel::Sample);
  std::vector<double> rows = {reference, reference, reference, v, v, v};
  std::vector<QualityEvent> events;
  screen.screen(rows.data(), rows.size(), events);
  return screen.counters()[0].quarantined;
}

TEST(InputScreenScaleBlock, VerdictAtTheLimitsIsTheDivisionsToTheLastBit) {
  const InputScreenParams p;
  int checked = 0;
  for (const double r : {0.3, 0.7, 1.0 / 3.0, 0.1, 0.06, 2.5e-5, 123.456}) {
    for (const double limit : {p.scale_collapse, p.scale_explosion}) {
      double v = limit * r;
      for (int s = 0; s < 4; ++s) v = std::nextafter(v, 0.0);
      for (int s = 0; s < 9; ++s, v = std::nextafter(v, 1e300)) {
        // A value above explosion x r (the product, as rounded) is one out-of-range value and never reaches the
        // block (with sudden_run 0 nothing quarantines then); one at or below it that divides to more than
        // explosion does.
        const bool in_block = !(v > p.scale_explosion * r);
        const bool expected = in_block && (v / r < p.scale_collapse || v / r > p.scale_explosion);
        EXPECT_EQ(quarantined_at(r, v), expected) << "reference " << r << ", value " << v;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 7 * 2 * 9);
}

// Events of several channels in one frame come in the order the values arrive (row, then channel), whichever
// channel runs ahead in the screen's common case.
TEST(InputScreenEvents, SeveralChannelsInOneFrameAreReportedInArrivalOrder) {
  InputScreen screen(kScreen, 3, ScreenLevel::Sample);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> rows(3 * 12);
  for (double& x : rows) x = normal(rng);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  rows[3 * 3 + 2] = nan;    // row 3, channel 3
  rows[3 * 3 + 0] = 1e9;    // row 3, channel 1: above the physical limit
  rows[5 * 3 + 1] = nan;    // row 5, channel 2
  rows[9 * 3 + 0] = nan;    // row 9, channel 1
  rows[9 * 3 + 2] = 2e9;    // row 9, channel 3
  screen.continue_at(100);
  std::vector<QualityEvent> events;
  screen.screen(rows.data(), 12, events);
  const std::vector<std::pair<std::uint64_t, int>> expected = {{103, 0}, {103, 2}, {105, 1}, {109, 0}, {109, 2}};
  ASSERT_EQ(events.size(), expected.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].index, expected[i].first) << i;
    EXPECT_EQ(events[i].channel, expected[i].second) << i;
  }
  EXPECT_EQ(events[0].kind, QualityEventKind::OutOfRange);
  EXPECT_EQ(events[1].kind, QualityEventKind::NonFinite);
  EXPECT_TRUE(std::isnan(rows[3 * 3 + 0]) && std::isnan(rows[9 * 3 + 2]));
  EXPECT_EQ(screen.counters()[0].screened + screen.counters()[1].screened + screen.counters()[2].screened, 36u);
}

TEST(InputScreenParameters, InvalidThresholdsThrowAtConstructionAndRefuseTheFirstFrame) {
  InputScreenParams bad;
  bad.scale_collapse = 2.0;
  EXPECT_THROW(InputScreen(bad, 4, ScreenLevel::Sample), std::invalid_argument);
  bad = InputScreenParams{};
  bad.recovery_samples = bad.scale_window - 1;
  EXPECT_THROW(InputScreen(bad, 4, ScreenLevel::Sample), std::invalid_argument);
  EXPECT_THROW(InputScreen(InputScreenParams{}, 0, ScreenLevel::Sample), std::invalid_argument);
  AssetPipelineParams p;
  p.sample.noise.fixed = estimation::NoiseParams{1e-6, 1.0, 1.0};
  p.frame_screen.max_abs_value = 0.0;
  AssetPipeline pipe(p);
  PipelineOutput out;
  const auto check = pipe.feed_frame(RowMajorMatrix::Ones(8, kG), 0, 0, true, false, false, 0, 20'000.0, out);
  EXPECT_FALSE(check.ok);
  EXPECT_NE(check.problem.find("max_abs_value"), std::string::npos) << check.problem;
}

}  // namespace

// A stopped machine (every channel at the ADC's quantisation floor, as IMS test 2's last
// snapshot: -0.005, -0.002, 0, +0.002) is an operating state, not 4 stuck channels: nothing is quarantined, the
// values pass, MachineStopped then MachineRunning are reported. One channel at the floor alone stays a fault.
namespace {
RowMajorMatrix running_rows(std::mt19937_64& rng, Eigen::Index n) {
  std::normal_distribution<double> noise(0.0, 0.08);
  RowMajorMatrix y(n, kG);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int j = 0; j < kG; ++j) y(i, j) = std::round(noise(rng) / 0.002) * 0.002;  // 12-bit-like steps
  return y;
}
RowMajorMatrix stopped_rows(std::mt19937_64& rng, Eigen::Index n) {
  const double levels[] = {-0.005, -0.002, -0.002, 0.0, 0.0, 0.002};
  std::uniform_int_distribution<int> pick(0, 5);
  RowMajorMatrix y(n, kG);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int j = 0; j < kG; ++j) y(i, j) = levels[pick(rng)];
  return y;
}
// Frames of 1024 running rows through `screen`, its events appended.
void run_frames(InputScreen& screen, std::mt19937_64& rng, int frames, std::vector<QualityEvent>& events) {
  for (int f = 0; f < frames; ++f) {
    RowMajorMatrix y = running_rows(rng, 1024);
    screen.screen(y.data(), 1024, events);
  }
}
std::size_t count_kind(const std::vector<QualityEvent>& events, QualityEventKind kind) {
  return static_cast<std::size_t>(std::count_if(events.begin(), events.end(), [&](const auto& e) { return e.kind == kind; }));
}
// Whole frames, calls of random sizes and one row per call give the same values, events and counters: the
// screen's common case judges long stretches of clean values at once (their runs restarted, the scale block
// filled), one row per call judges each value by itself, and random call sizes move the stretches' ends over the
// data. The data hit every boundary of that: quantised noise with exact repeats, +0 / -0 pairs (equal, different
// bits), exact zeros (below the collapse limit, repeated), short and long runs below the collapse limit, a stuck
// run, NaN, inf and huge values. With runs of 3 quarantining, a run's length one off anywhere shows as an event.
struct ScreenRun {
  std::vector<double> out;
  std::vector<QualityEvent> events;
  std::vector<ChannelQualityCounters> counters;
};

ScreenRun screen_in_calls(const InputScreenParams& p, const std::vector<double>& rows, std::size_t g,
                          std::size_t per_call, std::uint64_t seed) {
  InputScreen screen(p, static_cast<int>(g), ScreenLevel::Sample);
  ScreenRun r{rows, {}, {}};
  std::mt19937_64 rng(seed);
  const std::size_t n = rows.size() / g;
  for (std::size_t i = 0; i < n;) {
    const std::size_t m = std::min(per_call > 0 ? per_call : 1 + rng() % 300, n - i);
    screen.screen(r.out.data() + i * g, m, r.events);
    i += m;
  }
  r.counters = screen.counters();
  return r;
}

void expect_same_screening(const ScreenRun& a, const ScreenRun& b, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(a.out.size(), b.out.size());
  EXPECT_EQ(std::memcmp(a.out.data(), b.out.data(), a.out.size() * sizeof(double)), 0);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t e = 0; e < a.events.size(); ++e) {
    SCOPED_TRACE("event " + std::to_string(e));
    EXPECT_SAME_FIELDS(a.events[e], b.events[e], channel, kind, index, count, reason);
  }
  ASSERT_EQ(a.counters.size(), b.counters.size());
  for (std::size_t j = 0; j < a.counters.size(); ++j) {
    SCOPED_TRACE("channel " + std::to_string(j));
    EXPECT_SAME_FIELDS(a.counters[j], b.counters[j], screened, non_finite, out_of_range, quarantined_values, stuck,
                       scale_change, recovered, quarantined, reference_scale);
  }
}

TEST(InputScreenStretches, WholeFramesEqualOneRowPerCallToTheBit) {
  constexpr std::size_t g = 4, n = 6 * 1024 + 300;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> rows(g * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < g; ++j) rows[i * g + j] = std::round(normal(rng) * (j == 0 ? 3.0 : 200.0)) / 64.0;
    if (uniform(rng) < 0.04) rows[i * g + 1] = 0.0;  // exact zeros: low, and repeated now and then
  }
  for (std::size_t i = 2000; i < 2010; i += 2) rows[i * g + 1] = 0.0, rows[(i + 1) * g + 1] = -0.0;
  for (std::size_t i = 3000; i < 3020; ++i) rows[i * g + 2] = 1e-7;                           // low, short
  for (std::size_t i = 4100; i < 4140; ++i) rows[i * g + 2] = 1e-7 * static_cast<double>(i);  // sudden run
  for (std::size_t i = 5000; i < 5300; ++i) rows[i * g + 3] = 0.25;                           // stuck run
  rows[1500 * g + 3] = std::numeric_limits<double>::quiet_NaN();
  rows[1501 * g + 3] = std::numeric_limits<double>::infinity();
  rows[2047 * g + 0] = 1e9;
  rows[6100 * g + 1] = 5e5;  // within the physical limit, far above the channel's scale
  InputScreenParams shipped = InputScreenParams::for_samples();
  shipped.stopped_max_levels = 0;  // no stopped-machine verdict: it judges whole calls only
  InputScreenParams tight = shipped;  // runs of 3 quarantine; blocks of 64
  tight.stuck_samples = 3;
  tight.sudden_run = 3;
  tight.scale_window = 64;
  tight.recovery_samples = 64;
  for (const InputScreenParams& p : {shipped, tight}) {
    const ScreenRun single = screen_in_calls(p, rows, g, 1, 0);
    EXPECT_GE(single.events.size(), 5u);  // the faults above were seen (non-finite, out of range, quarantines)
    for (std::size_t j = 0; j < g; ++j) EXPECT_EQ(single.counters[j].screened, n);
    expect_same_screening(screen_in_calls(p, rows, g, 1024, 0), single, "frames of 1024 rows");
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      expect_same_screening(screen_in_calls(p, rows, g, 0, seed), single, "calls of random sizes");
    }
  }
}

}  // namespace

TEST(InputScreenStoppedMachine, EveryChannelAtTheQuantisationFloorIsAnOperatingStateNotAFault) {
  std::mt19937_64 rng(24);
  InputScreen screen(kScreen, kG, ScreenLevel::Sample);
  std::vector<QualityEvent> events;
  run_frames(screen, rng, 8, events);
  ASSERT_TRUE(events.empty());
  for (int f = 0; f < 20; ++f) {  // one IMS snapshot: 20 frames of 1024 rows
    RowMajorMatrix y = stopped_rows(rng, 1024);
    const RowMajorMatrix before = y;
    screen.screen(y.data(), 1024, events);
    EXPECT_TRUE(y == before) << "stopped-machine values pass unchanged (frame " << f << ")";
  }
  EXPECT_TRUE(screen.machine_stopped());
  EXPECT_EQ(screen.stopped_rows(), 20u * 1024u);
  EXPECT_EQ(count_kind(events, QualityEventKind::MachineStopped), 1u);
  EXPECT_EQ(count_kind(events, QualityEventKind::Stuck) + count_kind(events, QualityEventKind::ScaleChange), 0u);
  for (const auto& c : screen.counters()) EXPECT_FALSE(c.quarantined);
  RowMajorMatrix y = running_rows(rng, 1024);
  screen.screen(y.data(), 1024, events);
  EXPECT_FALSE(screen.machine_stopped());
  EXPECT_EQ(count_kind(events, QualityEventKind::MachineRunning), 1u);
  EXPECT_FALSE(y.hasNaN());
}

TEST(InputScreenStoppedMachine, OneChannelAtTheFloorWhileTheOthersRunIsStillQuarantined) {
  std::mt19937_64 rng(25);
  InputScreen screen(kScreen, kG, ScreenLevel::Sample);
  std::vector<QualityEvent> events;
  run_frames(screen, rng, 8, events);
  for (int f = 0; f < 8; ++f) {
    RowMajorMatrix y = running_rows(rng, 1024);
    y.col(1).setZero();  // a dead channel
    screen.screen(y.data(), 1024, events);
  }
  EXPECT_FALSE(screen.machine_stopped());
  EXPECT_EQ(count_kind(events, QualityEventKind::MachineStopped), 0u);
  EXPECT_TRUE(screen.counters()[1].quarantined);
}

}  // namespace causal::pipeline
