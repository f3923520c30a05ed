// twin-web's port, read from what it prints when it serves: shared by the integration and the browser tests.
#pragma once

#include "process_runner.hpp"

#include <chrono>
#include <regex>
#include <string>
#include <thread>

namespace causal::test {

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

}  // namespace causal::test
