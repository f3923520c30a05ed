// Command-line options that several executables register the same way (one text each): a configuration file
// whose default the one search chooses, and --max-runtime.
#pragma once

#include "causal/config/config_search.hpp"

#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>

namespace causal::config {

// A YAML file option (--params, --actions, --alarms-config): given on the command line, else the configuration
// search's choice of `file_name` (flag, $CAUSAL_TWIN_CONFIG_DIR, build tree, /etc/causal-twin,
// <prefix>/share/causal-twin/config, in that order), which --help names.
class ConfigFileOption {
 public:
  // Sets `path` to the search's choice and registers `flag` for it ("<what>; default: <the choice>", an existing
  // file). `path` is read after the parse: a field of the options, living as long as the app.
  ConfigFileOption(CLI::App& app, std::string flag, std::string& path, std::string file_name, const std::string& what)
      : flag_(std::move(flag)),
        file_name_(std::move(file_name)),
        choice_(find_config_file(file_name_, "", ConfigKind::Parameters)) {
    path = choice_.path;
    app.add_option(flag_, path, what + "; default: " + describe())->check(CLI::ExistingFile);
  }

  // "alarms.yaml from /etc/causal-twin" or "alarms.yaml not found (looked in: ...)".
  std::string describe() const { return choice_.describe(file_name_); }

  // Throws std::invalid_argument ("<describe()>: give <flag> FILE") when `path` is empty: neither the flag nor
  // the search gave a file.
  void require(const std::string& path) const {
    if (path.empty()) throw std::invalid_argument(describe() + ": give " + flag_ + " FILE");
  }

 private:
  std::string flag_;
  std::string file_name_;
  ConfigChoice choice_;
};

// --max-runtime SECONDS, as every long-running service reads it: exit after that long in any case (0 = never).
inline CLI::Option* add_max_runtime_option(CLI::App& app, double& max_runtime_s) {
  return app.add_option("--max-runtime", max_runtime_s, "exit after this many seconds in any case (0 = never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

}  // namespace causal::config
