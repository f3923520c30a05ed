// What every JSON route of twin-web answers with: the status, no caching (the answers are live state), and the
// body serialised with invalid UTF-8 replaced (names come from DDS data, not from us); and the wall clock the
// page's requests are stamped with (an operator's action happens now, not at a snapshot's time).
#pragma once

#include "http_server.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>

namespace causal::web {

inline void send_json(HttpResponse& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

inline std::int64_t wall_clock_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace causal::web
