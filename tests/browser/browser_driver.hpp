// What the Chromium tests share: playwright-core in the build folder, twin-web's port and the driver script's
// RESULT line.
// Needs BROWSER_TEST_SOURCE_DIR and NPM_BIN (the tests' compile definitions, tests/browser/CMakeLists.txt).
#pragma once

#include "process_runner.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>

namespace causal::test {

// playwright-core in `dir` (`npm ci` from the committed lock file when it is not there yet: needs the network
// once), with the driver script `driver` and the module it imports (drive_common.mjs) copied beside it (node
// resolves packages from the script's folder up).
inline bool ensure_node_modules(const std::filesystem::path& dir, const std::string& driver,
                                const std::filesystem::path& log) {
  namespace fs = std::filesystem;
  const fs::path source(BROWSER_TEST_SOURCE_DIR);
  fs::create_directories(dir);
  for (const std::string& f : {driver, std::string("drive_common.mjs")}) {
    fs::copy_file(source / f, dir / f, fs::copy_options::overwrite_existing);
  }
  if (fs::exists(dir / "node_modules" / "playwright-core" / "package.json")) return true;
  for (const char* f : {"package.json", "package-lock.json"}) {
    fs::copy_file(source / f, dir / f, fs::copy_options::overwrite_existing);
  }
  ServiceProcess npm("npm", {NPM_BIN, "ci", "--no-audit", "--no-fund", "--prefix", dir.string()}, log.string());
  const auto code = npm.wait(std::chrono::seconds(240));
  return code && *code == 0 && fs::exists(dir / "node_modules" / "playwright-core" / "package.json");
}

// The port twin-web printed ("serving http://127.0.0.1:PORT/"), waiting for it (bounded); 0 when it did not.
inline int served_port(ServiceProcess& web, std::chrono::seconds timeout) {
  const std::regex served(R"(serving http://127\.0\.0\.1:(\d+)/)");
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline && web.running()) {
    std::smatch m;
    const std::string out = web.output();
    if (std::regex_search(out, m, served)) return std::stoi(m[1]);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return 0;
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
