// Bounds on a YAML file before yaml-cpp builds a tree of it. Parameter and plant files are small, hand-written
// maps; a file that is not (a huge scalar, nesting thousands deep, anchors and aliases that expand to billions of
// nodes, a flood of nodes) is refused with a message naming the file and the line, instead of growing the
// process. yaml-cpp 0.7 itself stops nesting only at 2000 levels and keeps every node (about 0.3 kB each).
#pragma once

#include <cstddef>
#include <string>

namespace causal::config {

inline constexpr std::size_t kMaxYamlBytes = 1024 * 1024;  // the largest shipped file is 6 kB
inline constexpr std::size_t kMaxYamlDepth = 32;           // maps and sequences within each other
inline constexpr std::size_t kMaxYamlNodes = 100000;       // scalars, maps and sequences

// The text of a YAML file of at most kMaxYamlBytes. Throws ConfigError naming the file when it cannot be read
// or is larger.
std::string read_yaml_file(const std::string& path);

// Checks the first document of `text` against the bounds; anchors (&name) and aliases (*name) are refused
// outright (a parameter file never needs them, and an alias is how one line expands to a billion nodes).
// Throws ConfigError "<source>: line L: <problem>"; YAML syntax errors are left to the loader.
void check_yaml_bounds(const std::string& text, const std::string& source);

}  // namespace causal::config
