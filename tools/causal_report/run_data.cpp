#include "run_data.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"

#include "causal/io/time_format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

namespace causal::report {

using io::CsvTable;
using io::read_csv;

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }
bool ends_with(const std::string& s, const std::string& p) {
  return s.size() >= p.size() && s.compare(s.size() - p.size(), p.size(), p) == 0;
}

std::optional<double> utc_seconds(const std::string& cell) {
  if (cell.empty()) return std::nullopt;
  const auto ns = io::parse_utc(cell);
  if (!ns) return std::nullopt;
  return static_cast<double>(*ns) * 1e-9;
}

std::optional<int> parse_digits(const std::string& s) {
  if (s.empty() || s.size() > 6) return std::nullopt;
  int v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + (c - '0');
  }
  return v;
}

// Column of a required header name, or a clear error naming the file.
std::size_t need(const CsvTable& t, const std::string& name) {
  const int c = t.column(name);
  if (c < 0) throw std::runtime_error(t.path + ": no column '" + name + "'");
  return static_cast<std::size_t>(c);
}

double cell_number(const std::string& cell) { return CsvTable::number(cell).value_or(kNaN); }

// Time of a row: time_ns when present and numeric, else time_utc.
double row_time(const CsvTable& t, const std::vector<std::string>& row, int ns_col, int utc_col) {
  if (ns_col >= 0) {
    if (const auto v = CsvTable::number(row[static_cast<std::size_t>(ns_col)])) return *v * 1e-9;
  }
  if (utc_col >= 0) {
    if (const auto v = utc_seconds(row[static_cast<std::size_t>(utc_col)])) return *v;
  }
  (void)t;
  return kNaN;
}

// Every row whose time is known: its time (seconds) appended to `times`, then use(row).
template <class Use>
void for_each_timed_row(const CsvTable& t, std::vector<double>& times, Use use) {
  const int ns_col = t.column("time_ns"), utc_col = t.column("time_utc");
  for (const auto& row : t.rows) {
    const double time = row_time(t, row, ns_col, utc_col);
    if (!std::isfinite(time)) continue;
    times.push_back(time);
    use(row);
  }
}

}  // namespace

const char* severity_colour(Severity s) {
  switch (s) {
    case Severity::Advisory: return "#D4A500";  // amber, still readable on white
    case Severity::Warning: return "#F06C00";   // orange
    case Severity::Critical: return "#D00000";  // red
  }
  return "#808080";
}

std::optional<FactorName> parse_factor_name(const std::string& name, int channel_count) {
  if (name.size() < 3 || name[0] != 'x') return std::nullopt;
  std::string rest = name.substr(1);
  FactorName f;
  bool lagged = false;
  if (rest[0] == 'L') {
    lagged = true;
    f.lag = 1;
    rest = rest.substr(1);
  }
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const std::size_t us = rest.find('_', start);
    parts.push_back(rest.substr(start, us == std::string::npos ? std::string::npos : us - start));
    if (us == std::string::npos) break;
    start = us + 1;
  }
  std::optional<int> k, j, lag;
  if (parts.size() == 1) {  // fewer than 10 channels: one digit each for k and j, lag digits before them
    const std::string& d = parts[0];
    if (d.size() < 2 || (!lagged && d.size() != 2)) return std::nullopt;
    k = parse_digits(d.substr(d.size() - 2, 1));
    j = parse_digits(d.substr(d.size() - 1));
    if (d.size() > 2) lag = parse_digits(d.substr(0, d.size() - 2));
  } else if (parts.size() == 2) {
    k = parse_digits(parts[0]);
    j = parse_digits(parts[1]);
  } else if (parts.size() == 3 && lagged) {
    lag = parse_digits(parts[0]);
    k = parse_digits(parts[1]);
    j = parse_digits(parts[2]);
    if (!lag) return std::nullopt;
  } else {
    return std::nullopt;
  }
  if (!k || !j || *k < 1 || *j < 1) return std::nullopt;
  if (channel_count > 0 && (*k > channel_count || *j > channel_count)) return std::nullopt;
  if (lag) {
    if (*lag < 2) return std::nullopt;  // lag 1 is written "xL{k}{j}" without a number
    f.lag = *lag;
  }
  f.outcome = *k;
  f.source = *j;
  return f;
}

RunFiles discover_run(const fs::path& run_dir) {
  RunFiles run;
  std::map<std::string, AssetFiles> assets;
  std::error_code ec;
  std::vector<fs::path> files;
  for (fs::directory_iterator it(run_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file(ec)) files.push_back(it->path());
  }
  if (ec) throw std::runtime_error("cannot list '" + run_dir.string() + "': " + ec.message());
  std::sort(files.begin(), files.end());
  for (const auto& path : files) {
    const std::string name = path.filename().string();
    if (!ends_with(name, ".csv")) continue;
    const std::string stem = name.substr(0, name.size() - 4);
    if (starts_with(stem, "conditions_")) {
      // conditions_<asset>_<feature>: features have no '_', asset ids may.
      const std::string body = stem.substr(11);
      const std::size_t us = body.rfind('_');
      if (us == std::string::npos || us == 0 || us + 1 == body.size()) continue;
      auto& a = assets[body.substr(0, us)];
      a.conditions.emplace_back(body.substr(us + 1), path);
      ++run.csv_count;
    } else if (starts_with(stem, "factors_")) {
      const std::string body = stem.substr(8);
      for (const char* scale : {"_sample_", "_condition_"}) {
        for (const char* kind : {"filter", "fixed-lag", "rts"}) {
          const std::string suffix = std::string(scale) + kind;
          if (!ends_with(body, suffix) || body.size() == suffix.size()) continue;
          ++run.csv_count;
          if (std::string(scale) != "_condition_") continue;  // sample-level factors are not plotted
          auto& a = assets[body.substr(0, body.size() - suffix.size())];
          if (std::string(kind) == "filter") a.factors_filter = path;
          if (std::string(kind) == "fixed-lag") a.factors_fixed_lag = path;
        }
      }
    } else if (name == "alarms.csv") {
      run.alarms = path;
      ++run.csv_count;
    }
  }
  if (!run.alarms.empty()) {
    const CsvTable t = read_csv(run.alarms);
    const std::size_t col = need(t, "asset_group");
    for (const auto& row : t.rows) assets[io::safe_file_component(row[col])];
  }
  for (auto& [id, a] : assets) {
    a.asset = id;
    run.assets.push_back(std::move(a));
  }
  return run;
}

ConditionSeries load_conditions(const fs::path& file, const std::string& feature) {
  const CsvTable t = read_csv(file);
  ConditionSeries s;
  s.feature = feature;
  if (t.column("time_ns") < 0 && t.column("time_utc") < 0) {
    throw std::runtime_error(t.path + ": no time_ns or time_utc column");
  }
  // Channels: every column after snapshot,time_ns,time_utc.
  const std::size_t first = 3;
  if (t.header.size() <= first) throw std::runtime_error(t.path + ": no channel columns");
  s.channels.assign(t.header.begin() + static_cast<long>(first), t.header.end());
  s.values.assign(s.channels.size(), {});
  for_each_timed_row(t, s.t, [&](const std::vector<std::string>& row) {
    for (std::size_t c = 0; c < s.channels.size(); ++c) s.values[c].push_back(cell_number(row[first + c]));
  });
  return s;
}

FactorSeries load_factors(const fs::path& file, const std::string& kind) {
  const CsvTable t = read_csv(file);
  FactorSeries s;
  s.kind = kind;
  std::vector<std::size_t> value_cols, sd_cols;
  for (std::size_t c = 0; c < t.header.size(); ++c) {
    if (starts_with(t.header[c], "nis_")) s.outcome_names.push_back(t.header[c].substr(4));
  }
  const int g = static_cast<int>(s.outcome_names.size());
  for (std::size_t c = 3; c < t.header.size(); ++c) {
    const std::string& h = t.header[c];
    if (starts_with(h, "sd_") || starts_with(h, "nis_")) continue;
    const auto parsed = parse_factor_name(h, g);
    const int sd = t.column("sd_" + h);
    if (!parsed || sd < 0) continue;  // not a factor column
    s.names.push_back(h);
    s.outcome.push_back(parsed->outcome - 1);
    value_cols.push_back(c);
    sd_cols.push_back(static_cast<std::size_t>(sd));
  }
  s.mean.assign(s.names.size(), {});
  s.sd.assign(s.names.size(), {});
  for_each_timed_row(t, s.t, [&](const std::vector<std::string>& row) {
    for (std::size_t f = 0; f < s.names.size(); ++f) {
      s.mean[f].push_back(cell_number(row[value_cols[f]]));
      s.sd[f].push_back(cell_number(row[sd_cols[f]]));
    }
  });
  return s;
}

std::vector<AlarmRecord> load_alarms(const fs::path& file, const std::string& asset) {
  const CsvTable t = read_csv(file);
  const std::size_t id = need(t, "alarm_id"), state = need(t, "state"), severity = need(t, "severity"),
                    kind = need(t, "kind"), group = need(t, "asset_group"), channel = need(t, "channel"),
                    channel_name = need(t, "channel_name"), time = need(t, "time_utc"), raised = need(t, "raised_utc"),
                    cleared = need(t, "cleared_utc"), root = need(t, "root_cause_channel"),
                    root_name = need(t, "root_cause_name"), reason = need(t, "reason");
  // Columns added later (category, root-cause confidence) are optional: older recordings still read.
  const int category = t.column("category"), index = t.column("sample_index"),
            confidence = t.column("root_cause_confidence");
  std::vector<AlarmRecord> out;
  for (const auto& row : t.rows) {
    if (!asset.empty() && io::safe_file_component(row[group]) != asset) continue;
    AlarmRecord r;
    if (category >= 0 && !row[static_cast<std::size_t>(category)].empty()) {
      r.category = row[static_cast<std::size_t>(category)];
    }
    if (index >= 0) r.sample_index = CsvTable::number(row[static_cast<std::size_t>(index)]);
    if (confidence >= 0) r.root_cause_confidence = CsvTable::number(row[static_cast<std::size_t>(confidence)]);
    r.alarm_id = row[id];
    r.state = row[state];
    r.severity = parse_severity(row[severity]).value_or(Severity::Advisory);
    r.kind = row[kind];
    r.asset_group = row[group];
    r.channel = static_cast<int>(CsvTable::number(row[channel]).value_or(0.0));
    r.channel_name = row[channel_name];
    r.time = utc_seconds(row[time]);
    r.raised = utc_seconds(row[raised]);
    r.cleared = utc_seconds(row[cleared]);
    r.raised_utc = row[raised];
    r.cleared_utc = row[cleared];
    r.root_cause_channel = static_cast<int>(CsvTable::number(row[root]).value_or(0.0));
    r.root_cause_name = row[root_name];
    r.reason = row[reason];
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<AlarmSpan> build_alarm_spans(const std::vector<AlarmRecord>& rows, double end_time) {
  struct Change {
    double at;
    Severity severity;
  };
  std::vector<AlarmSpan> spans;
  std::map<std::string, std::size_t> by_id;
  std::vector<std::vector<Change>> changes;
  for (const auto& r : rows) {
    auto [it, is_new] = by_id.emplace(r.alarm_id, spans.size());
    if (is_new) {
      AlarmSpan s;
      s.alarm_id = r.alarm_id;
      s.kind = r.kind;
      s.channel = r.channel;
      s.channel_name = r.channel_name;
      s.first_severity = s.max_severity = r.severity;
      spans.push_back(std::move(s));
      changes.emplace_back();
    }
    AlarmSpan& s = spans[it->second];
    if (r.raised && (s.raised_utc.empty() || r.state == "raised")) {
      s.raised = *r.raised;
      s.raised_utc = r.raised_utc;
    }
    if (r.state == "raised") s.first_severity = r.severity;
    if (r.cleared) {
      s.cleared = r.cleared;
      s.cleared_utc = r.cleared_utc;
    }
    if (r.root_cause_channel > 0 || !r.root_cause_name.empty()) {  // latest explanation wins
      s.root_cause_channel = r.root_cause_channel;
      s.root_cause_name = r.root_cause_name;
    }
    s.max_severity = std::max(s.max_severity, r.severity);
    if (r.state == "escalated" && r.time) changes[it->second].push_back({*r.time, r.severity});
  }
  for (std::size_t i = 0; i < spans.size(); ++i) {
    AlarmSpan& s = spans[i];
    const double stop = s.cleared ? *s.cleared : std::max(end_time, s.raised);
    auto& c = changes[i];
    std::sort(c.begin(), c.end(), [](const Change& a, const Change& b) { return a.at < b.at; });
    double from = s.raised;
    Severity sev = s.first_severity;
    for (const auto& change : c) {
      const double at = std::clamp(change.at, s.raised, stop);
      if (at > from) s.segments.push_back({from, at, sev});
      from = at;
      sev = change.severity;
    }
    s.segments.push_back({from, std::max(from, stop), sev});
  }
  return spans;
}

}  // namespace causal::report
