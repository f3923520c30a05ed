// What every JSON route of twin-web answers with: the status, no caching (the answers are live state), and the
// body serialised with invalid UTF-8 replaced (names come from DDS data, not from us). The page's requests are
// stamped with the wall clock, io::utc_now_ns() (an operator's action happens now, not at a snapshot's time).
#pragma once

#include "http_server.hpp"

#include "causal/io/time_format.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace causal::web {

inline void send_json(HttpResponse& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

// A request twin-web did not carry out: {"answered": false, "error": why}.
inline void send_unanswered(HttpResponse& res, int status, const std::string& why) {
  send_json(res, status, {{"answered", false}, {"error", why}});
}

// A POST's JSON body; when the body is not JSON, answered with 400 here and nullopt.
inline std::optional<nlohmann::json> json_body(const HttpRequest& req, HttpResponse& res) {
  nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
  if (body.is_discarded()) {
    send_unanswered(res, 400, "the body is not JSON");
    return std::nullopt;
  }
  return body;
}

}  // namespace causal::web
