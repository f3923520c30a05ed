// Runs a helper program (gnuplot) as a child process: no shell, output to a log file, bounded time.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace causal::report {

// `name` itself when it contains a '/' and is executable, else the first executable PATH entry.
std::optional<std::filesystem::path> find_executable(const std::string& name);

struct ProcessResult {
  bool started = false;
  bool timed_out = false;  // killed (our child, by pid) after the time limit
  int exit_code = -1;      // exit status, or 128 + signal
};

// argv[0] is the program path. stdout and stderr go to log_file (truncated).
ProcessResult run_process(const std::vector<std::string>& argv, const std::filesystem::path& log_file,
                          std::chrono::seconds time_limit = std::chrono::seconds(120));

}  // namespace causal::report
