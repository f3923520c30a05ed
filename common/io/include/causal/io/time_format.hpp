// UTC time stamps <-> nanoseconds since the Unix epoch (proleptic Gregorian calendar, no leap seconds,
// no time zones: the IMS file names are local wall-clock times that we treat as UTC throughout).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace causal::io {

// "2004-02-12 10:32:39"; if time_ns is not a whole second, ".mmm" (milliseconds, truncated towards the
// past) is appended: "2004-02-12 10:32:39.250". Negative times (before 1970) are supported.
std::string format_utc(std::int64_t time_ns);

// "2004-02-12 10:32:39 UTC": whole seconds (truncated towards the past) and the zone spelt out, for
// plain-language text (alarm reasons, advice, causal-alarm-eval).
std::string format_utc_seconds(std::int64_t time_ns);

// Like format_utc but exact: appends the shortest of ".mmm", ".mmmuuu", ".mmmuuunnn" that represents
// time_ns without loss, so parse_utc(format_utc_exact(t)) == t for every t.
std::string format_utc_exact(std::int64_t time_ns);

// Accepts "YYYY-MM-DD hh:mm:ss", "YYYY-MM-DDThh:mm:ss" (optional trailing 'Z'), each with an optional
// fraction ".f" of 1..9 digits, and the IMS file-name form "YYYY.MM.DD.hh.mm.ss". Fields are
// range-checked (day within the month, hh < 24, mm < 60, ss < 60). Leading/trailing blanks are ignored.
[[nodiscard]] std::optional<std::int64_t> parse_utc(std::string_view text);

// The system clock now, in ns since the Unix epoch (what every wall-clock stamp of the services uses).
std::int64_t utc_now_ns();

// Civil date/time -> ns since epoch; no range checking (callers validate). Exposed for the tests and
// for tools that build time axes.
std::int64_t utc_to_ns(int year, int month, int day, int hour, int minute, int second);

}  // namespace causal::io
