// Helpers for the delivery-contract fault tests ("nothing lost, nothing stalls"): private domain ids, the
// services' machine-readable exit lines, the recorder's "lost snapshots" ranges, recorded CSV files, and a
// guard that always resumes a process the test froze (a stopped process cannot even handle SIGTERM).
#pragma once

#include <gtest/gtest.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <sys/types.h>
#include <unistd.h>
#include <vector>

#include "test_files.hpp"

namespace causal::test::delivery {

namespace fs = std::filesystem;

// The fault tests' domain ids are 200..231, one fixed id per test (list in tests/fault/CMakeLists.txt), so
// ctest -j never puts two tests on one domain; the integration tests use 100..199.
inline int delivery_domain_id(int salt) {
  return 200 + salt;  // a fixed id per test: ctest -j runs tests side by side (see CMakeLists.txt)
}

inline fs::path work_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_delivery", name); }

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// One `summary topic=T key=value ...` line of a service log.
struct Summary {
  std::string topic;
  std::map<std::string, std::uint64_t> counts;
};

inline std::vector<Summary> summaries(const std::string& log) {
  static const std::regex line_re(R"(summary topic=(\S+)((?: \w+=\d+)*))");
  static const std::regex pair_re(R"((\w+)=(\d+))");
  std::vector<Summary> out;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), line_re); it != std::sregex_iterator(); ++it) {
    Summary s;
    s.topic = (*it)[1];
    const std::string rest = (*it)[2];
    for (auto p = std::sregex_iterator(rest.begin(), rest.end(), pair_re); p != std::sregex_iterator(); ++p) {
      s.counts[(*p)[1]] = std::stoull((*p)[2]);
    }
    out.push_back(std::move(s));
  }
  return out;
}

// The count `key` of the summary line of `topic`; nullopt when the service printed no such line.
inline std::optional<std::uint64_t> summary_count(const std::string& log, const std::string& topic,
                                                  const std::string& key) {
  for (const auto& s : summaries(log)) {
    if (s.topic != topic) continue;
    const auto it = s.counts.find(key);
    if (it != s.counts.end()) return it->second;
  }
  return std::nullopt;
}

// Every summary line's lost/dropped/failed/refused count must be 0. Returns the offending "topic key=n".
inline std::vector<std::string> nonzero_losses(const std::string& log) {
  std::vector<std::string> bad;
  for (const auto& s : summaries(log)) {
    for (const char* key : {"lost", "dropped", "failed", "refused", "rejected"}) {
      const auto it = s.counts.find(key);
      if (it != s.counts.end() && it->second != 0) bad.push_back(s.topic + " " + key + "=" + std::to_string(it->second));
    }
  }
  return bad;
}

// The recorder's exit line for one condition file: "condition vectors FILE: received R, written W,
// duplicates D, refused F[; lost snapshots a..b, c, ...]".
struct RecorderConditionLine {
  bool found = false;
  std::uint64_t received = 0, written = 0, duplicates = 0, refused = 0;
  std::set<std::uint64_t> lost;  // every snapshot the recorder names as lost
  bool truncated = false;        // the log listed only the first ranges ("and N more")
};

inline RecorderConditionLine recorder_condition_line(const std::string& log, const std::string& file) {
  RecorderConditionLine r;
  const std::regex re("condition vectors " + std::regex_replace(file, std::regex(R"([.^$|()\[\]{}*+?\\-])"), R"(\$&)") +
                      R"(: received (\d+), written (\d+), duplicates (\d+), refused (\d+)(?:; lost snapshots ([^\n]*))?)");
  std::smatch m;
  if (!std::regex_search(log, m, re)) return r;
  r.found = true;
  r.received = std::stoull(m[1]);
  r.written = std::stoull(m[2]);
  r.duplicates = std::stoull(m[3]);
  r.refused = std::stoull(m[4]);
  const std::string ranges = m[5];
  r.truncated = ranges.find("more") != std::string::npos;
  static const std::regex range_re(R"((\d+)(?:\.\.(\d+))?)");
  for (auto it = std::sregex_iterator(ranges.begin(), ranges.end(), range_re); it != std::sregex_iterator(); ++it) {
    if (r.truncated && std::next(it) == std::sregex_iterator()) break;  // the "N" of "and N more"
    const std::uint64_t a = std::stoull((*it)[1]);
    const std::uint64_t b = (*it)[2].matched ? std::stoull((*it)[2]) : a;
    for (std::uint64_t i = a; i <= b; ++i) r.lost.insert(i);
  }
  return r;
}

// A recorded CSV file: data rows (header excluded) and the integers of its first column (snapshot or
// sample index), with the ones seen more than once.
struct RecordedFile {
  bool exists = false;
  std::uint64_t bytes = 0;
  std::uint64_t rows = 0;
  std::set<std::uint64_t> indices;
  std::vector<std::uint64_t> repeated;
  std::uint64_t unparsable = 0;
};

inline RecordedFile read_recorded(const fs::path& path) {
  RecordedFile f;
  std::ifstream in(path);
  if (!in) return f;
  f.exists = true;
  f.bytes = fs::file_size(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    ++f.rows;
    const std::string first = line.substr(0, line.find(','));
    try {
      std::size_t used = 0;
      const std::uint64_t index = std::stoull(first, &used);
      if (used != first.size()) throw std::invalid_argument(first);
      if (!f.indices.insert(index).second) f.repeated.push_back(index);
    } catch (const std::exception&) {
      ++f.unparsable;
    }
  }
  return f;
}

// "a..b, c" for a sorted set of indices (test messages).
inline std::string ranges_text(const std::set<std::uint64_t>& s, std::size_t max_ranges = 12) {
  std::ostringstream out;
  std::size_t shown = 0;
  for (auto it = s.begin(); it != s.end();) {
    auto last = it;
    while (std::next(last) != s.end() && *std::next(last) == *last + 1) ++last;
    if (shown++ == max_ranges) {
      out << ", ...";
      break;
    }
    out << (shown > 1 ? ", " : "") << *it;
    if (*last != *it) out << ".." << *last;
    it = std::next(last);
  }
  return out.str();
}

// Resumes a process the test stopped with SIGSTOP, whatever path the test leaves by (a failed ASSERT
// included): a stopped child would otherwise ignore the SIGTERM of its ServiceProcess destructor.
class FrozenProcess {
 public:
  explicit FrozenProcess(pid_t pid) : pid_(pid) { stopped_ = ::kill(pid_, SIGSTOP) == 0; }
  ~FrozenProcess() { resume(); }
  FrozenProcess(const FrozenProcess&) = delete;
  FrozenProcess& operator=(const FrozenProcess&) = delete;
  bool stopped() const { return stopped_; }
  void resume() {
    if (stopped_) ::kill(pid_, SIGCONT);
    stopped_ = false;
  }

 private:
  pid_t pid_;
  bool stopped_ = false;
};

}  // namespace causal::test::delivery
