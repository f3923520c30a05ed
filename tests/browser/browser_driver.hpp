// What the Chromium tests share: playwright-core in the build folder, twin-web's port and the driver script's
// RESULT line.
// Needs BROWSER_TEST_SOURCE_DIR, BROWSER_TEST_BINARY_DIR, CHROMIUM_BIN and NPM_BIN (the tests' compile definitions, tests/browser/CMakeLists.txt).
#pragma once

#include "process_runner.hpp"
#include "served_port.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>
#include <vector>

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

// The folders of a Chromium test in this build's tests/browser: node/ (playwright-core and the drivers) and
// output/ (screenshots and logs); `work` is output/<work_name>, made fresh, when the test names one.
struct BrowserFolders {
  std::filesystem::path node, out, work;
};

// Chromium installed, the folders made, playwright-core and each driver in node/ (npm ci the first time); a
// failure says what is missing. Use as ASSERT_TRUE(prepare_browser_test(...)).
inline ::testing::AssertionResult prepare_browser_test(BrowserFolders& f, const std::vector<std::string>& drivers,
                                                       const std::string& work_name = "") {
  namespace fs = std::filesystem;
  if (!fs::exists(CHROMIUM_BIN)) {
    return ::testing::AssertionFailure() << CHROMIUM_BIN << " missing: run deploy/install_deps.sh (Debian chromium)";
  }
  f.node = fs::path(BROWSER_TEST_BINARY_DIR) / "node";
  f.out = fs::path(BROWSER_TEST_BINARY_DIR) / "output";
  fs::create_directories(f.out);
  if (!work_name.empty()) {
    f.work = f.out / work_name;
    fs::remove_all(f.work);
    fs::create_directories(f.work);
  }
  for (const std::string& driver : drivers) {
    if (!ensure_node_modules(f.node, driver, f.out / "npm.log")) {
      return ::testing::AssertionFailure() << "npm ci failed, see " << (f.out / "npm.log");
    }
  }
  return ::testing::AssertionSuccess();
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
