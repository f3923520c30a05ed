// GET /api/history?group=ID&from=UTC&to=UTC: a range of the historian's database (twin-web --db), in the same JSON
// as /api/state?group=ID (the page draws it with the same code). The handler is plain logic (parameters in,
// status and body out); web_server.cpp only routes to it.
#pragma once

#include "causal/history/history_store.hpp"

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

namespace causal::web {

struct HistoryReply {
  int status = 200;
  std::string body;  // JSON
};

class HistoryRoutes {
 public:
  // store may be null (twin-web without --db): every request is answered 404 with that reason.
  explicit HistoryRoutes(history::HistoryStore* store, std::size_t max_points) : store_(store), max_points_(max_points) {}
  // group required; from/to: UTC times as parse_utc reads them ("2004-02-12 10:32:39", "2004-02-12T10:32:39Z"),
  // either may be empty (open end). A bad parameter answers 400 naming it.
  HistoryReply range(const std::string& group, const std::string& from, const std::string& to);

 private:
  history::HistoryStore* store_;
  std::size_t max_points_;
  std::mutex mutex_;  // one connection: a PostgreSQL connection serves one query at a time
};

}  // namespace causal::web
