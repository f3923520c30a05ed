// The prognosis in words (common/prognosis prognosis_text.hpp): the log and Prognosis.text form, and the operator's
// rounded AssetStatus form. Expected texts worked out by hand from the hours and the data time.
#include "causal/prognosis/prognosis_text.hpp"

#include "causal/io/time_format.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace causal::prognosis {
namespace {

ChannelPrognosis warning_in_12h() {
  ChannelPrognosis p;
  p.channel = 0;
  p.level = Level::warning;
  p.ratio = 2.0;
  p.time.known = true;
  p.time.hours = 12.34;
  p.time.hours_low = 6.14;
  p.time.hours_high = 29.7;
  return p;
}

TEST(PrognosisText, StatusLineInRoundedHoursAndUtc) {
  ChannelPrognosis p = warning_in_12h();
  const std::int64_t at = *io::parse_utc("2004-02-19 06:00:00");
  EXPECT_EQ(status_prognosis_text("bearing1", p, at), "bearing1: warning in ~12 h (6.1-30 h), ~2004-02-19 18:00 UTC");
  p.level = Level::critical;
  p.time.known = false;
  p.time.why = "no rising trend";
  EXPECT_EQ(status_prognosis_text("bearing1", p, at), "bearing1: critical: unknown (no rising trend)");
  p.time.reached = true;
  EXPECT_EQ(status_prognosis_text("bearing1", p, at), "bearing1: critical reached");
  p.level = Level::end_of_life;
  EXPECT_EQ(status_prognosis_text("bearing1", p, at), "bearing1: end of life reached");
}

// 12.34 h after 06:00 is 18:20:24 (whole minutes: 18:20), 6.14 h is 12:08:24, 29.7 h is 11:42 the next day.
TEST(PrognosisText, FullTextWithIntervalAndUtcToTheMinute) {
  ChannelPrognosis p = warning_in_12h();
  const std::int64_t at = *io::parse_utc("2004-02-19 06:00:00");
  EXPECT_EQ(prognosis_text("bearing1", p, at, 0.9),
            "bearing1 reaches warning (2x its baseline) in 12 h (90 % interval 6.1 h to 30 h): 2004-02-19 18:20 UTC "
            "(between 2004-02-19 12:08 UTC and 2004-02-20 11:42 UTC)");
  EXPECT_EQ(eta_ns(at, 1.5), at + 5400LL * 1000000000LL);
  EXPECT_EQ(eta_ns(at, std::nan("")), 0);
  p.time.known = false;
  p.time.why = "no rising trend";
  EXPECT_EQ(prognosis_text("bearing1", p, at, 0.9), "bearing1: time to warning (2x its baseline) unknown: no rising trend");
  p.time.reached = true;
  p.current_ratio = 2.345;
  EXPECT_EQ(prognosis_text("bearing1", p, at, 0.9),
            "bearing1 has reached warning (2x its baseline): its level is 2.35x its baseline now");
  EXPECT_EQ(channel_label({"a", "b"}, 1), "b");
  EXPECT_EQ(channel_label({"a", "b"}, 4), "5");
}

}  // namespace
}  // namespace causal::prognosis
