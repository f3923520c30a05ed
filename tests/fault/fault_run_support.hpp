// Helpers of the crash and isolation fault tests: a private domain id (delivery_checks.hpp), the services' command
// lines as deploy/launch.sh runs them, bounded waits, and readers of what causal-recorder wrote (its CSV files),
// so a test compares recordings of real runs over DDS.
#pragma once

#include "delivery_checks.hpp"
#include "process_runner.hpp"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace causal::test::fault {

namespace fs = std::filesystem;

inline int domain_id(int salt) { return delivery::delivery_domain_id(salt); }
using delivery::work_dir;

inline std::string feature_table() {
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
}
inline std::string transport() { return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"; }

using delivery::read_text;

// Bounded poll: true once `done` holds, false at the deadline.
inline bool wait_until(const std::function<bool()>& done, std::chrono::seconds bound) {
  const auto end = std::chrono::steady_clock::now() + bound;
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

// One CSV line split into cells (RFC 4180 quotes, as causal-recorder writes them; no multi-line cells).
inline std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cells.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r') {
      cells.back() += c;
    }
  }
  return cells;
}

// A recorded CSV: its header, its rows as raw lines (for byte comparisons) and as cells.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::string> lines;
  std::vector<std::vector<std::string>> rows;
  int column(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  }
};

inline CsvTable read_csv(const fs::path& path) {
  CsvTable t;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return t;
  t.header = split_csv(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    t.lines.push_back(line);
    t.rows.push_back(split_csv(line));
  }
  return t;
}

// The snapshot indices of a recorded table's first column, in file order.
inline std::vector<std::uint64_t> indices(const CsvTable& t) {
  std::vector<std::uint64_t> out;
  for (const auto& r : t.rows) out.push_back(std::stoull(r.at(0)));
  return out;
}

// Recorded rows of a table: the number of lines after the header (0 while the file does not exist).
inline std::size_t recorded_rows(const fs::path& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n > 0 ? n - 1 : 0;
}

// The recorder's factor tables of one asset group at condition level (filter, fixed lag), by file name.
inline std::map<std::string, fs::path> condition_factor_files(const fs::path& dir, const std::string& group) {
  std::map<std::string, fs::path> out;
  const std::string prefix = "factors_" + group + "_condition_";
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0) out[name] = e.path();
  }
  return out;
}

// The alarm history of a recording, per alarm id: kind, channel and the events (state, severity, snapshot
// index) in the order they were recorded. Cross-id order depends on delivery timing; per id it is the order
// the recommender published.
struct AlarmHistory {
  std::string kind, channel;
  std::vector<std::string> events;  // "state/severity/index"
  std::vector<std::string> lines;   // the raw recorded rows
  bool operator==(const AlarmHistory& o) const { return kind == o.kind && channel == o.channel && events == o.events; }
};

inline std::map<std::string, AlarmHistory> alarm_histories(const CsvTable& alarms, const std::string& group) {
  std::map<std::string, AlarmHistory> out;
  const int id = alarms.column("alarm_id"), state = alarms.column("state"), severity = alarms.column("severity"),
            kind = alarms.column("kind"), asset = alarms.column("asset_group"), channel = alarms.column("channel"),
            index = alarms.column("sample_index");
  for (std::size_t i = 0; i < alarms.rows.size(); ++i) {
    const auto& r = alarms.rows[i];
    if (r.at(static_cast<std::size_t>(asset)) != group) continue;
    AlarmHistory& h = out[r.at(static_cast<std::size_t>(id))];
    h.kind = r.at(static_cast<std::size_t>(kind));
    h.channel = r.at(static_cast<std::size_t>(channel));
    h.events.push_back(r.at(static_cast<std::size_t>(state)) + "/" + r.at(static_cast<std::size_t>(severity)) + "/" +
                       r.at(static_cast<std::size_t>(index)));
    h.lines.push_back(alarms.lines[i]);
  }
  return out;
}

inline std::string describe(const std::map<std::string, AlarmHistory>& alarms) {
  std::string s;
  for (const auto& [id, h] : alarms) {
    s += "  " + id + " " + h.kind + " ch" + h.channel + ":";
    for (const auto& e : h.events) s += " " + e;
    s += "\n";
  }
  return s;
}

// The first match of `pattern`'s group 1 in a log, or "?".
inline std::string grab(const std::string& log, const std::string& pattern) {
  std::smatch m;
  if (std::regex_search(log, m, std::regex(pattern)) && m.size() > 1) return m[1].str();
  return "?";
}

// The last match of `pattern`'s group 1 in a log (e.g. the last progress line), or "?".
inline std::string grab_last(const std::string& log, const std::string& pattern) {
  const std::regex re(pattern);
  std::string last = "?";
  for (auto it = std::sregex_iterator(log.begin(), log.end(), re); it != std::sregex_iterator(); ++it) last = (*it)[1].str();
  return last;
}

// Ids an alarm-recommender log says it raised ("ALARM raised <id> [").
inline std::vector<std::string> raised_ids(const std::string& log) {
  std::vector<std::string> out;
  static const std::regex re(R"(ALARM raised (\S+) \[)");
  for (auto it = std::sregex_iterator(log.begin(), log.end(), re); it != std::sregex_iterator(); ++it) {
    out.push_back((*it)[1].str());
  }
  return out;
}

}  // namespace causal::test::fault
