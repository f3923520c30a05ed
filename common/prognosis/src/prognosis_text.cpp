#include "causal/prognosis/prognosis_text.hpp"

#include "causal/io/time_format.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace causal::prognosis {

namespace {

constexpr double kNsPerHour = 3.6e12;

std::string hours_text(double h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, h < 10 ? "%.1f h" : "%.0f h", h);
  return buf;
}

// Whole minutes: a prognosis is not more precise than that.
std::string utc(std::int64_t time_ns) {
  const std::int64_t minute = 60LL * 1000000000LL;
  const std::string s = io::format_utc((time_ns / minute) * minute);
  return s.substr(0, 16) + " UTC";
}

// Two significant digits (0.5 h, 12 h, 120 h): the interval is far wider than the third digit.
std::string rounded_hours(double h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", h);
  double v = std::strtod(buf, nullptr);
  std::snprintf(buf, sizeof buf, v < 10 ? "%.1f" : "%.0f", v);
  std::string s = buf;
  if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
  return s;
}

// To the hour: the operator plans a shift, and the line does not change with every snapshot.
std::string utc_hour(std::int64_t time_ns) {
  const std::int64_t hour = 3600LL * 1000000000LL;
  const std::int64_t rounded = ((time_ns + hour / 2) / hour) * hour;
  return io::format_utc(rounded).substr(0, 16) + " UTC";
}

}  // namespace

std::int64_t eta_ns(std::int64_t time_ns, double hours) {
  return std::isfinite(hours) ? time_ns + static_cast<std::int64_t>(std::llround(hours * kNsPerHour)) : 0;
}

std::string channel_label(const std::vector<std::string>& channel_names, int channel) {
  return channel >= 0 && static_cast<std::size_t>(channel) < channel_names.size()
             ? channel_names[static_cast<std::size_t>(channel)]
             : std::to_string(channel + 1);
}

std::string status_prognosis_text(const std::string& channel_name, const ChannelPrognosis& p, std::int64_t time_ns) {
  std::string level = to_string(p.level);  // "end_of_life" reads "end of life"
  for (auto& c : level) c = c == '_' ? ' ' : c;
  const std::string head = channel_name + ": " + level;
  const TimeToLevel& t = p.time;
  if (t.reached) return head + " reached";
  if (!t.known) return head + ": unknown" + (t.why.empty() ? std::string() : " (" + t.why + ")");
  return head + " in ~" + rounded_hours(t.hours) + " h (" + rounded_hours(t.hours_low) + "-" +
         rounded_hours(t.hours_high) + " h), ~" + utc_hour(eta_ns(time_ns, t.hours));
}

std::string prognosis_text(const std::string& channel_name, const ChannelPrognosis& p, std::int64_t time_ns,
                           double coverage) {
  char ratio[48];
  std::snprintf(ratio, sizeof ratio, "%s (%gx its baseline)", to_string(p.level), p.ratio);
  const TimeToLevel& t = p.time;
  if (t.reached) {
    char now[32];
    std::snprintf(now, sizeof now, "%.2fx", p.current_ratio);
    return channel_name + " has reached " + ratio + ": its level is " + now + " its baseline now";
  }
  if (!t.known) return channel_name + ": time to " + ratio + " unknown: " + t.why;
  char pct[16];
  std::snprintf(pct, sizeof pct, "%g %%", 100.0 * coverage);
  return channel_name + " reaches " + ratio + " in " + hours_text(t.hours) + " (" + pct + " interval " +
         hours_text(t.hours_low) + " to " + hours_text(t.hours_high) + "): " + utc(eta_ns(time_ns, t.hours)) +
         " (between " + utc(eta_ns(time_ns, t.hours_low)) + " and " + utc(eta_ns(time_ns, t.hours_high)) + ")";
}

}  // namespace causal::prognosis
