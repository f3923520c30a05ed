#include "causal/io/input_error.hpp"

#include <utility>

namespace causal::io {

InputError::InputError(std::string file, std::size_t line, const std::string& problem)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + problem),
      file_(std::move(file)),
      line_(line),
      problem_(problem) {}

}  // namespace causal::io
