// Error thrown by the readers in causal_io when an input file is unusable.
// It names the file and the 1-based line so an operator can open the file at the fault.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace causal::io {

// what() = "<file>:<line>: <problem>". Line 0 means the problem concerns the whole file
// (missing, unreadable, empty, no snapshot in a directory, ...).
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::size_t line, const std::string& problem);

  const std::string& file() const noexcept { return file_; }
  std::size_t line() const noexcept { return line_; }
  // The problem text alone, without the "<file>:<line>: " prefix.
  const std::string& problem() const noexcept { return problem_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string problem_;
};

}  // namespace causal::io
