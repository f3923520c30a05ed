// The command-line conventions every tool shares (README "Command-line conventions"): one long name per
// thing (--domain, --transport, --asset-group, --out, --params, --features, --max-runtime, --log-level),
// old spellings kept as aliases on the same option, and --version on every installed tool.
#pragma once

#include <CLI/CLI.hpp>

#include "causal/config/exit_codes.hpp"
#include <string>

namespace causal::config {

// The project version, as printed by every tool's --version.
inline std::string tool_version() { return CAUSAL_TWIN_VERSION; }

// --version: prints the project version and exits 0. A tool that catches CLI::ParseError itself must catch
// CLI::Success (help, version) first and return app.exit(e).
inline void add_version_flag(CLI::App& app) { app.set_version_flag("--version", tool_version()); }

// The exit code of a command line CLI11 refused: 0 for --help/--version (printed), else 2 after CLI11's message
// (it names the option: "The following argument was not expected: --metrics-prot"). Every tool exits 2 on a usage
// error, as its --help says; CLI11's own codes (105 conversion, 106 validation, 109 extras, ...) never leak: a
// systemd unit's RestartPreventExitStatus=2 must stop a service started with a typo.
inline int usage_exit_code(const CLI::App& app, const CLI::Error& e) {
  const int code = app.exit(e);
  return code == 0 ? kExitOk : kExitUsage;
}

}  // namespace causal::config

// CLI11_PARSE with the exit codes above: returns from main() on --help/--version (0) or a usage error (2).
#define CAUSAL_CLI_PARSE(app, argc, argv)                                  \
  do {                                                                     \
    try {                                                                  \
      (app).parse((argc), (argv));                                         \
    } catch (const CLI::ParseError& cli_error_) {                          \
      return ::causal::config::usage_exit_code((app), cli_error_);         \
    }                                                                      \
  } while (false)

namespace causal::config {

}  // namespace causal::config
