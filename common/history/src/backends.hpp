// The two backends of HistoryStore (not part of the public interface).
#pragma once

#include "causal/history/history_store.hpp"

namespace causal::history {

std::unique_ptr<HistoryStore> open_sqlite(const std::string& path);
// Throws HistoryError when this build has no libpq.
std::unique_ptr<HistoryStore> open_postgres(const std::string& url);
std::string redact_url(const std::string& url);

}  // namespace causal::history
