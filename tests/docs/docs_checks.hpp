// Checks that what README.md and docs/ quote is real: repository paths exist, quoted tools are built and answer
// --help (exit 0) and know the options quoted with them, scripts know their quoted options, and links between
// pages resolve (file and heading anchor). Only quotes (code spans, fenced lines) and links are read, never
// prose, so a reworded sentence cannot fail the check.
#pragma once

#include "markdown_quotes.hpp"

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace causal::docs {

namespace fs = std::filesystem;

struct Problem {
  std::string page;  // page path relative to the source tree
  int line = 0;
  std::string what;
};

struct CheckReport {
  std::vector<Problem> problems;
  std::vector<std::string> notes;  // what was skipped and why (printed, never a failure)
  int checked = 0;                 // how many quotes / links were checked
};

// The tree the pages describe: its files and the executables of its build tree.
struct Repository {
  fs::path source;
  fs::path build;
  bool benchmarks_built = true;                    // tests/bench executables exist in the build tree
  std::vector<std::string> files;                  // every source file, relative, '/'-separated
  std::map<std::string, fs::path> executables;     // built executable name -> its path
};

// Walks the source tree (without .git, build trees and node_modules) and the build tree's executables.
Repository load_repository(const fs::path& source, const fs::path& build, bool benchmarks_built);

// README.md and every docs/**/*.md, relative to the source tree.
std::vector<std::string> documentation_pages(const fs::path& source);

// Pages other work of this round adds; links to them are checked only once they exist.
const std::set<std::string>& pages_expected_after_merge();

// Runs `<exe> --help` (and `<exe> --version`), remembering each answer.
class HelpCache {
 public:
  struct Answer {
    int exit_code = -1;
    std::string text;
  };
  const Answer& help(const fs::path& executable) { return run(executable, "--help"); }
  const Answer& version(const fs::path& executable) { return run(executable, "--version"); }
  const Answer& run(const fs::path& executable, const std::string& flag);

 private:
  std::map<std::string, Answer> answers_;
};

CheckReport check_paths(const Repository& repo, const std::string& page, const MarkdownPage& scanned);
CheckReport check_commands(const Repository& repo, const std::string& page, const MarkdownPage& scanned,
                           HelpCache& help);
CheckReport check_links(const Repository& repo, const std::string& page, const MarkdownPage& scanned);

// A tool name of this product (causal-*, sensor-*, alarm-*, twin-*, causal_bench_*, ims-variants).
bool looks_like_product_tool(const std::string& word);

std::string format(const std::vector<Problem>& problems);

}  // namespace causal::docs
