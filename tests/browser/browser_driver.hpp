// What the Chromium tests share: playwright-core in the build folder and the driver script's RESULT line.
// Needs BROWSER_TEST_SOURCE_DIR and NPM_BIN (the tests' compile definitions, tests/browser/CMakeLists.txt).
#pragma once

#include "process_runner.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <string>

namespace causal::test {

// playwright-core in `dir` (`npm ci` from the committed lock file when it is not there yet: needs the network
// once), with the driver script `driver` copied beside it (node resolves packages from the script's folder up).
inline bool ensure_node_modules(const std::filesystem::path& dir, const std::string& driver,
                                const std::filesystem::path& log) {
  namespace fs = std::filesystem;
  const fs::path source(BROWSER_TEST_SOURCE_DIR);
  fs::create_directories(dir);
  fs::copy_file(source / driver, dir / driver, fs::copy_options::overwrite_existing);
  if (fs::exists(dir / "node_modules" / "playwright-core" / "package.json")) return true;
  for (const char* f : {"package.json", "package-lock.json"}) {
    fs::copy_file(source / f, dir / f, fs::copy_options::overwrite_existing);
  }
  ServiceProcess npm("npm", {NPM_BIN, "ci", "--no-audit", "--no-fund", "--prefix", dir.string()}, log.string());
  const auto code = npm.wait(std::chrono::seconds(240));
  return code && *code == 0 && fs::exists(dir / "node_modules" / "playwright-core" / "package.json");
}

// The JSON after the driver's last "RESULT " line (a discarded value when there is none or it does not parse).
inline nlohmann::json driver_result(const std::string& output) {
  const auto at = output.rfind("RESULT ");
  if (at == std::string::npos) return nlohmann::json();
  const auto end = output.find('\n', at);
  return nlohmann::json::parse(output.substr(at + 7, end == std::string::npos ? std::string::npos : end - at - 7),
                               nullptr, false);
}

}  // namespace causal::test
