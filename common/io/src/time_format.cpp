#include "causal/io/time_format.hpp"

#include <chrono>
#include <cstdio>

#include "text_scan.hpp"

namespace causal::io {
namespace {

constexpr std::int64_t kNsPerSec = 1'000'000'000;
constexpr std::int64_t kSecPerDay = 86'400;

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil algorithm,
// http://howardhinnant.github.io/date_algorithms.html): exact for all int years, no tables, no locale.
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);                  // [0, 399]
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;  // [0, 365]
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;            // [0, 146096]
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

// Inverse of days_from_civil.
void civil_from_days(std::int64_t z, std::int64_t& y, unsigned& m, unsigned& d) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  y = static_cast<std::int64_t>(yoe) + era * 400;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  d = doy - (153 * mp + 2) / 5 + 1;
  m = mp < 10 ? mp + 3 : mp - 9;
  y += m <= 2 ? 1 : 0;
}

bool is_leap(std::int64_t y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

unsigned days_in_month(std::int64_t y, unsigned m) {
  static constexpr unsigned kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && is_leap(y) ? 29u : kDays[m - 1];
}

// Floor division / modulo so that times before 1970 format as the correct civil time.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

std::string format_seconds(std::int64_t secs) {
  const std::int64_t days = floor_div(secs, kSecPerDay);
  const std::int64_t sod = secs - days * kSecPerDay;
  std::int64_t y = 0;
  unsigned m = 0, d = 0;
  civil_from_days(days, y, m, d);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04lld-%02u-%02u %02lld:%02lld:%02lld", static_cast<long long>(y), m, d,
                static_cast<long long>(sod / 3600), static_cast<long long>(sod / 60 % 60),
                static_cast<long long>(sod % 60));
  return buf;
}

// Reads exactly n digits at s[pos..]; advances pos.
bool read_digits(std::string_view s, std::size_t& pos, std::size_t n, std::int64_t& out) {
  if (pos + n > s.size()) return false;
  std::int64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const char c = s[pos + i];
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  pos += n;
  out = v;
  return true;
}

bool expect(std::string_view s, std::size_t& pos, char c) {
  if (pos >= s.size() || s[pos] != c) return false;
  ++pos;
  return true;
}

}  // namespace

std::int64_t utc_to_ns(int year, int month, int day, int hour, int minute, int second) {
  const std::int64_t days = days_from_civil(year, static_cast<unsigned>(month), static_cast<unsigned>(day));
  return ((days * 24 + hour) * 60 + minute) * 60 * kNsPerSec + static_cast<std::int64_t>(second) * kNsPerSec;
}

std::int64_t utc_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string format_utc(std::int64_t time_ns) {
  const std::int64_t secs = floor_div(time_ns, kNsPerSec);
  const std::int64_t frac = time_ns - secs * kNsPerSec;  // [0, 1e9)
  std::string s = format_seconds(secs);
  if (frac != 0) {
    char buf[32];
    std::snprintf(buf, sizeof buf, ".%03lld", static_cast<long long>(frac / 1'000'000));
    s += buf;
  }
  return s;
}

std::string format_utc_seconds(std::int64_t time_ns) { return format_seconds(floor_div(time_ns, kNsPerSec)) + " UTC"; }

std::string format_utc_exact(std::int64_t time_ns) {
  const std::int64_t secs = floor_div(time_ns, kNsPerSec);
  const std::int64_t frac = time_ns - secs * kNsPerSec;
  std::string s = format_seconds(secs);
  if (frac != 0) {
    char buf[32];
    if (frac % 1'000'000 == 0) {
      std::snprintf(buf, sizeof buf, ".%03lld", static_cast<long long>(frac / 1'000'000));
    } else if (frac % 1'000 == 0) {
      std::snprintf(buf, sizeof buf, ".%06lld", static_cast<long long>(frac / 1'000));
    } else {
      std::snprintf(buf, sizeof buf, ".%09lld", static_cast<long long>(frac));
    }
    s += buf;
  }
  return s;
}

std::optional<std::int64_t> parse_utc(std::string_view text) {
  const std::string_view s = detail::trim(text);
  std::size_t p = 0;
  std::int64_t y = 0, mo = 0, d = 0, h = 0, mi = 0, se = 0, frac_ns = 0;
  if (!read_digits(s, p, 4, y)) return std::nullopt;
  if (p >= s.size()) return std::nullopt;
  const char sep = s[p];
  if (sep == '.') {
    // IMS file-name form YYYY.MM.DD.hh.mm.ss (no fraction: the next '.' would be ambiguous).
    if (!expect(s, p, '.') || !read_digits(s, p, 2, mo) || !expect(s, p, '.') || !read_digits(s, p, 2, d) ||
        !expect(s, p, '.') || !read_digits(s, p, 2, h) || !expect(s, p, '.') || !read_digits(s, p, 2, mi) ||
        !expect(s, p, '.') || !read_digits(s, p, 2, se) || p != s.size()) {
      return std::nullopt;
    }
  } else {
    if (!expect(s, p, '-') || !read_digits(s, p, 2, mo) || !expect(s, p, '-') || !read_digits(s, p, 2, d)) {
      return std::nullopt;
    }
    if (p >= s.size() || (s[p] != ' ' && s[p] != 'T')) return std::nullopt;
    ++p;
    if (!read_digits(s, p, 2, h) || !expect(s, p, ':') || !read_digits(s, p, 2, mi) || !expect(s, p, ':') ||
        !read_digits(s, p, 2, se)) {
      return std::nullopt;
    }
    if (p < s.size() && s[p] == '.') {
      ++p;
      std::int64_t scale = 100'000'000;
      std::size_t n = 0;
      while (p < s.size() && s[p] >= '0' && s[p] <= '9') {
        if (++n > 9) return std::nullopt;
        frac_ns += (s[p] - '0') * scale;
        scale /= 10;
        ++p;
      }
      if (n == 0) return std::nullopt;
    }
    if (p < s.size() && s[p] == 'Z') ++p;
    if (p != s.size()) return std::nullopt;
  }
  if (mo < 1 || mo > 12 || d < 1 || d > days_in_month(y, static_cast<unsigned>(mo)) || h > 23 || mi > 59 ||
      se > 59) {
    return std::nullopt;
  }
  return utc_to_ns(static_cast<int>(y), static_cast<int>(mo), static_cast<int>(d), static_cast<int>(h),
                   static_cast<int>(mi), static_cast<int>(se)) +
         frac_ns;
}

}  // namespace causal::io
