// SourceHealth (common/dds source_health.hpp): when a source counts as silent and when it is back, driven by
// a fake clock (time points built by hand), so every deadline is checked to the millisecond.
#include "causal/dds/source_health.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace {

using causal::dds::HealthChange;
using causal::dds::SourceHealth;
using Kind = HealthChange::Kind;

// The fake clock: t(1.5) is 1.5 s after an arbitrary origin.
SourceHealth::Clock::time_point t(double s) {
  return SourceHealth::Clock::time_point{} + std::chrono::duration_cast<SourceHealth::Clock::duration>(
                                                 std::chrono::duration<double>(1000.0 + s));
}

TEST(SourceHealth, LiveSourceRaisesExactlyAtTheDeadlineAndClearsOnData) {
  SourceHealth h(30.0);
  std::vector<HealthChange> out;
  h.on_data("g1", 7, t(0), out);
  h.on_data("g1", 8, t(10), out);
  h.check(t(39.999), out);  // 29.999 s after the last data: not yet
  EXPECT_TRUE(out.empty());
  h.check(t(40.0), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, Kind::Raised);
  EXPECT_EQ(out[0].source, "g1");
  EXPECT_TRUE(out[0].has_index);
  EXPECT_EQ(out[0].last_index, 8u);
  EXPECT_NEAR(out[0].silent_s, 30.0, 1e-6);
  EXPECT_NE(out[0].reason.find("deadline of 30.0 s"), std::string::npos) << out[0].reason;
  EXPECT_NE(out[0].reason.find("30.0 s ago (snapshot 8)"), std::string::npos) << out[0].reason;
  out.clear();
  h.check(t(100), out);  // one alarm per silence
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(h.active_alarms(), 1u);
  h.on_data("g1", 9, t(105), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, Kind::Cleared);
  EXPECT_EQ(out[0].last_index, 8u);  // the alarm's snapshot (its id), not the new one
  EXPECT_NEAR(out[0].silent_s, 95.0, 1e-6);
  EXPECT_EQ(h.active_alarms(), 0u);
  EXPECT_EQ(h.raised(), 1u);
  EXPECT_EQ(h.cleared(), 1u);
}

TEST(SourceHealth, LostWriterRaisesAtOnceAndANewWriterClears) {
  SourceHealth h(30.0);
  std::vector<HealthChange> out;
  h.on_data("g1", 3, t(0), out);
  h.on_writer_lost("g1", t(6), out);  // well before the deadline
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, Kind::Raised);
  EXPECT_NEAR(out[0].silent_s, 6.0, 1e-6);
  EXPECT_NE(out[0].reason.find("writer was lost"), std::string::npos) << out[0].reason;
  out.clear();
  h.check(t(60), out);  // the deadline adds nothing to an open alarm
  EXPECT_TRUE(out.empty());
  h.on_data("g1", 4, t(70), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, Kind::Cleared);
  out.clear();
  // Alive again: the deadline applies again, from the new data.
  h.check(t(99.9), out);
  EXPECT_TRUE(out.empty());
  h.check(t(100), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].last_index, 4u);
}

TEST(SourceHealth, CleanEndIsNotAFault) {
  SourceHealth h(30.0);
  std::vector<HealthChange> out;
  h.on_data("g1", 1, t(0), out);
  h.on_ended("g1", t(1), out);
  h.on_writer_lost("g1", t(2), out);  // the writer leaves after disposing: still no fault
  h.check(t(1000), out);               // an ended source has no deadline
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(h.raised(), 0u);
  // It may start again (a new run); then it is watched again.
  h.on_data("g1", 2, t(2000), out);
  h.on_writer_lost("g1", t(2001), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, Kind::Raised);
}

TEST(SourceHealth, CleanEndClearsAStalledSourcesAlarm) {
  SourceHealth h(5.0);
  std::vector<HealthChange> out;
  h.on_data("g1", 1, t(0), out);
  h.check(t(5), out);
  ASSERT_EQ(out.size(), 1u);
  out.clear();
  h.on_ended("g1", t(8), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].kind, Kind::Cleared);
  EXPECT_NE(out[0].reason.find("ended cleanly"), std::string::npos) << out[0].reason;
}

TEST(SourceHealth, SourcesAreIndependent) {
  SourceHealth h(10.0);
  std::vector<HealthChange> out;
  h.on_data("a", 1, t(0), out);
  h.on_data("b", 1, t(5), out);
  h.check(t(10), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].source, "a");
  out.clear();
  h.on_data("a", 2, t(12), out);  // a clears; b is due at 15
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].source, "a");
  out.clear();
  h.check(t(15), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].source, "b");
  EXPECT_EQ(h.sources(), 2u);
  EXPECT_EQ(h.active_alarms(), 1u);
}

TEST(SourceHealth, ZeroDeadlineWatchesOnlyLostWriters) {
  SourceHealth h(0.0);
  std::vector<HealthChange> out;
  h.on_data("g1", 1, t(0), out);
  h.check(t(1e6), out);
  EXPECT_TRUE(out.empty());
  h.on_writer_lost("g1", t(1e6), out);
  EXPECT_EQ(out.size(), 1u);
}

TEST(SourceHealth, DataWithoutIndexAndNeverSeenSources) {
  SourceHealth h(10.0);
  std::vector<HealthChange> out;
  h.check(t(100), out);  // nothing known, nothing due
  EXPECT_TRUE(out.empty());
  h.on_writer_lost("never", t(1), out);  // a writer that never sent data and left
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].has_index);
  EXPECT_NE(out[0].reason.find("last data never"), std::string::npos) << out[0].reason;
  out.clear();
  h.on_data("plain", t(0), out);
  h.check(t(10), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].has_index);
}

TEST(SourceHealth, InvalidDeadlinesAreRefused) {
  EXPECT_THROW(SourceHealth(-1.0), std::invalid_argument);
  EXPECT_THROW(SourceHealth(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
  EXPECT_THROW(SourceHealth(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
