// The two backends of HistoryStore (not part of the public interface).
#pragma once

#include "causal/history/history_store.hpp"

namespace causal::history {

std::unique_ptr<HistoryStore> open_sqlite(const std::string& path);
// Throws HistoryError when this build has no libpq.
std::unique_ptr<HistoryStore> open_postgres(const std::string& url);
std::string redact_url(const std::string& url);

// Each backend's writes (add's rows, apply_retention's DELETEs): run(item) for every item in one transaction
// (exec(begin) ... exec("COMMIT")), the sum of the rows they changed; on an exception rollback() and rethrow, so
// the store is left without a transaction open.
template <class Items, class Exec, class Rollback, class Run>
std::size_t sum_in_transaction(const Items& items, const char* begin, Exec exec, Rollback rollback, Run run) {
  exec(begin);
  std::size_t changed = 0;
  try {
    for (const auto& item : items) changed += run(item);
    exec("COMMIT");
  } catch (...) {
    rollback();
    throw;
  }
  return changed;
}

}  // namespace causal::history
