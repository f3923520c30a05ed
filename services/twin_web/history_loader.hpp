// twin-web's history (--db): what the historian's database holds (common/history, docs/historian.md), turned back
// into the messages the live view takes, so a page after a restart of twin-web (or on a finished run with no
// publisher left) is complete. The live DDS data that follows is merged by TwinState as usual (a snapshot index
// or an alarm event it already has is not added twice).
#pragma once

#include "twin_state.hpp"

#include "causal/history/history_store.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace causal::web {

struct HistoryLoad {
  std::uint64_t condition_vectors = 0, alarm_events = 0, recommendations = 0, prognoses = 0, statuses = 0;
  std::uint64_t unreadable = 0;  // rows whose cells did not convert (counted, logged by the caller)
  std::optional<std::int64_t> earliest_ns;  // the oldest condition vector's time, nullopt = none
};

// Feeds state with every row of the query's range (asset group "" = all) in data order.
HistoryLoad load_history(history::HistoryStore& store, TwinState& state, const history::RangeQuery& range);

// Rows -> messages (exposed for the tests).
std::optional<causal_twin::ConditionVector> condition_from_row(const history::Row& row);
std::optional<causal_twin::Alarm> alarm_from_row(const history::Row& row);
std::optional<causal_twin::Recommendation> recommendation_from_row(const history::Row& row);
std::optional<causal_twin::Prognosis> prognosis_from_row(const history::Row& row);
std::optional<causal_twin::AssetStatus> status_from_row(const history::Row& row);

}  // namespace causal::web
