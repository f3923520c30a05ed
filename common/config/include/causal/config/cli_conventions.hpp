// The command-line conventions every tool shares (README "Command-line conventions"): one long name per
// thing (--domain, --transport, --asset-group, --out, --params, --features, --max-runtime, --log-level),
// old spellings kept as aliases on the same option, and --version on every installed tool.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace causal::config {

// The project version, as printed by every tool's --version.
inline std::string tool_version() { return CAUSAL_TWIN_VERSION; }

// --version: prints the project version and exits 0. A tool that catches CLI::ParseError itself must catch
// CLI::Success (help, version) first and return app.exit(e).
inline void add_version_flag(CLI::App& app) { app.set_version_flag("--version", tool_version()); }

}  // namespace causal::config
