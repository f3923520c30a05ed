// Where the tools find their configuration files (DDS XML profiles, parameter YAML), in one documented order:
//
//   1. the command-line flag (--qos, --transport, --params), when given;
//   2. the folder named by an environment variable (CAUSAL_TWIN_DDS_DIR for the DDS XML files,
//      CAUSAL_TWIN_CONFIG_DIR for the YAML parameter files);
//   3. only for a binary that lives in the build tree: the source tree's deploy/<dds|config>/;
//   4. /etc/causal-twin/ (the operator's site configuration; the package installs it there);
//   5. the files installed with the binary: <exe dir>/../share/causal-twin/<dds|config>/.
//
// The first place that holds the file wins, and the choice says where it came from (the tools print it in
// --help and log it). A build-tree binary reads its own source tree before /etc/causal-twin, so a developer
// machine with the package installed still builds and tests against the branch's files, never the installed
// ones. An installed binary never reads the source tree: step 3 is skipped unless the running executable is
// inside the build folder it was compiled for. Standard library only.
#pragma once

#include <string>
#include <vector>

namespace causal::config {

// The kinds of configuration file: the folder they live in under share/causal-twin/ and deploy/.
enum class ConfigKind { Dds, Parameters };

// Candidate folders, in search order, each with a short label for messages.
struct ConfigPlace {
  std::string dir;
  std::string label;  // e.g. "$CAUSAL_TWIN_DDS_DIR", "/etc/causal-twin", "installed", "build tree"
};

// The inputs of the search, separated from the process so the order can be tested.
struct SearchRoots {
  std::string env_dir;         // value of the environment variable ("" = unset)
  std::string env_name;        // its name, for the label
  std::string etc_dir = "/etc/causal-twin";
  std::string installed_dir;   // <exe dir>/../share/causal-twin/<sub>, "" when unknown
  std::string build_tree_dir;  // <source>/deploy/<sub>, "" unless the executable is in the build tree
};

struct ConfigChoice {
  std::string path;    // "" when the file was found nowhere
  std::string origin;  // "flag", or the label of the place
  std::vector<ConfigPlace> searched;  // every place looked at (for the error message)
  bool found() const { return !path.empty(); }
  // "qos.xml from /etc/causal-twin" or "qos.xml not found (looked in: ...)".
  std::string describe(const std::string& file_name) const;
};

// The roots of this process: the environment variable of `kind`, the source tree's deploy folder only when
// /proc/self/exe is under the build folder, /etc/causal-twin, and the install folder next to /proc/self/exe.
SearchRoots process_roots(ConfigKind kind);

// true when `path` is `dir` or below it, compared component by component after lexical normalisation (how
// process_roots decides that the executable lives in the build tree).
bool is_inside_dir(const std::string& path, const std::string& dir);

// Places in search order (empty roots left out): environment, build tree, /etc, installed.
std::vector<ConfigPlace> config_places(const SearchRoots& roots);

// The flag value when non-empty (it is not checked here: CLI11 checks that it exists), else the first place
// holding a regular file `file_name`.
ConfigChoice find_config_file(const std::string& file_name, const std::string& flag_value, const SearchRoots& roots);

// Same with process_roots(kind).
ConfigChoice find_config_file(const std::string& file_name, const std::string& flag_value, ConfigKind kind);

}  // namespace causal::config
