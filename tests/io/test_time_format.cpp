#include "causal/io/time_format.hpp"

#include <gtest/gtest.h>

#include <ctime>
#include <random>

using causal::io::format_utc;
using causal::io::format_utc_exact;
using causal::io::parse_utc;
using causal::io::utc_to_ns;

namespace {
constexpr std::int64_t kSec = 1'000'000'000;
// 2004-02-12 10:32:39 UTC = 1076581959 s (Python calendar.timegm).
constexpr std::int64_t kRunStart = 1076581959LL * kSec;
}  // namespace

TEST(TimeFormat, KnownValues) {
  EXPECT_EQ(utc_to_ns(1970, 1, 1, 0, 0, 0), 0);
  EXPECT_EQ(utc_to_ns(2004, 2, 12, 10, 32, 39), kRunStart);
  EXPECT_EQ(utc_to_ns(2004, 2, 29, 0, 0, 0), 1078012800LL * kSec);  // leap day
  EXPECT_EQ(utc_to_ns(1969, 12, 31, 23, 59, 59), -kSec);
}

TEST(TimeFormat, AgreesWithTimegmOnRandomDates) {
  // timegm (glibc) is an independent implementation of the same civil -> epoch conversion.
  std::mt19937_64 rng(20040212);
  std::uniform_int_distribution<int> year(1900, 2200), month(1, 12), day(1, 28), hour(0, 23), minute(0, 59);
  for (int i = 0; i < 2000; ++i) {
    std::tm tm{};
    tm.tm_year = year(rng) - 1900;
    tm.tm_mon = month(rng) - 1;
    tm.tm_mday = day(rng);
    tm.tm_hour = hour(rng);
    tm.tm_min = minute(rng);
    tm.tm_sec = minute(rng);
    const std::int64_t expect = static_cast<std::int64_t>(timegm(&tm)) * kSec;
    const std::int64_t got =
        utc_to_ns(tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec);
    ASSERT_EQ(got, expect) << "case " << i;
    // And the round trip through text.
    ASSERT_EQ(parse_utc(format_utc(got)), got) << format_utc(got);
  }
}

TEST(TimeFormat, FormatUtc) {
  EXPECT_EQ(format_utc(kRunStart), "2004-02-12 10:32:39");
  EXPECT_EQ(format_utc(kRunStart + 250'000'000), "2004-02-12 10:32:39.250");
  EXPECT_EQ(format_utc(kRunStart + 1'500), "2004-02-12 10:32:39.000");  // not whole: ms shown, truncated
  EXPECT_EQ(format_utc(0), "1970-01-01 00:00:00");
  EXPECT_EQ(format_utc(-1), "1969-12-31 23:59:59.999");  // floor, not truncation toward zero
  EXPECT_EQ(format_utc(utc_to_ns(2000, 2, 29, 23, 59, 59)), "2000-02-29 23:59:59");
}

TEST(TimeFormat, FormatExactRoundTrips) {
  const std::int64_t cases[] = {kRunStart, kRunStart + 50'000, kRunStart + 1, kRunStart + 123'000'000,
                                -1,        -123'456'789,       0,             kRunStart + 999'999'999};
  for (std::int64_t t : cases) {
    const std::string s = format_utc_exact(t);
    ASSERT_EQ(parse_utc(s), t) << s;
  }
  EXPECT_EQ(format_utc_exact(kRunStart + 50'000), "2004-02-12 10:32:39.000050");
  EXPECT_EQ(format_utc_exact(kRunStart + 1), "2004-02-12 10:32:39.000000001");
}

TEST(TimeFormat, ParseAcceptedForms) {
  EXPECT_EQ(parse_utc("2004-02-12 10:32:39"), kRunStart);
  EXPECT_EQ(parse_utc("  2004-02-12 10:32:39 "), kRunStart);
  EXPECT_EQ(parse_utc("2004-02-12T10:32:39Z"), kRunStart);
  EXPECT_EQ(parse_utc("2004.02.12.10.32.39"), kRunStart);
  EXPECT_EQ(parse_utc("2004-02-12 10:32:39.5"), kRunStart + 500'000'000);
  EXPECT_EQ(parse_utc("2004-02-12 10:32:39.000000007"), kRunStart + 7);
}

TEST(TimeFormat, ParseRejects) {
  for (const char* bad : {"", "2004-02-12", "2004-02-12 10:32", "2004-13-01 00:00:00", "2003-02-29 00:00:00",
                          "2004-02-30 00:00:00", "2004-02-12 24:00:00", "2004-02-12 10:60:00",
                          "2004-02-12 10:32:60", "2004-02-12 10:32:39.", "2004-02-12 10:32:39.1234567890",
                          "2004/02/12 10:32:39", "2004-02-12 10:32:39x", "2004.02.12.10.32", "04-02-12 10:32:39",
                          "2004.02.12.10.32.39.5"}) {
    EXPECT_FALSE(parse_utc(bad).has_value()) << "'" << bad << "'";
  }
}
