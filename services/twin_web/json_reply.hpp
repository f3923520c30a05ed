// What every JSON route of twin-web answers with: the status, no caching (the answers are live state), and the
// body serialised with invalid UTF-8 replaced (names come from DDS data, not from us). The page's requests are
// stamped with the wall clock, io::utc_now_ns() (an operator's action happens now, not at a snapshot's time).
#pragma once

#include "http_server.hpp"

#include "causal/io/time_format.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>

namespace causal::web {

inline void send_json(HttpResponse& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

}  // namespace causal::web
