#include "history_routes.hpp"

#include "history_loader.hpp"
#include "twin_state.hpp"

#include "causal/io/time_format.hpp"

#include <nlohmann/json.hpp>

namespace causal::web {

namespace {
HistoryReply error(int status, const std::string& why) {
  return {status, nlohmann::json{{"error", why}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)};
}
}  // namespace

HistoryReply HistoryRoutes::range(const std::string& group, const std::string& from, const std::string& to) {
  if (store_ == nullptr) return error(404, "no history: twin-web runs without --db");
  if (group.empty()) return error(400, "group is required");
  history::RangeQuery q;
  q.asset_group = group;
  if (!from.empty()) {
    q.from_ns = io::parse_utc(from);
    if (!q.from_ns) return error(400, "from: not a UTC time (e.g. 2004-02-12T10:32:39Z)");
  }
  if (!to.empty()) {
    q.to_ns = io::parse_utc(to);
    if (!q.to_ns) return error(400, "to: not a UTC time (e.g. 2004-02-12T10:32:39Z)");
  }
  if (q.from_ns && q.to_ns && *q.from_ns > *q.to_ns) return error(400, "from is after to");
  StateLimits limits;
  limits.trend_points = max_points_;
  TwinState state(limits);  // a view of the range alone, serialised like the live state
  HistoryLoad load;
  try {
    std::lock_guard<std::mutex> lock(mutex_);
    load = load_history(*store_, state, q);
  } catch (const history::HistoryError& e) {
    return error(503, e.what());
  }
  state.set_info("source", "history");
  state.set_info("from", from);
  state.set_info("to", to);
  state.set_info("unreadable_rows", std::to_string(load.unreadable));
  return {200, state.page_json(group)};
}

}  // namespace causal::web
