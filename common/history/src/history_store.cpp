#include "causal/history/history_store.hpp"

#include "backends.hpp"

namespace causal::history {

void HistoryStore::add(const std::string& table_name, Row row) {
  const Table& t = table(table_name);
  if (row.size() != t.columns.size()) {
    throw HistoryError("history table " + t.name + ": a row of " + std::to_string(row.size()) + " cells, the table has " +
                       std::to_string(t.columns.size()) + " columns");
  }
  for (std::size_t i = 0; i < row.size(); ++i) {
    const ColumnType type = t.columns[i].type;
    if (!row[i] || type == ColumnType::Text) continue;
    // An empty number is unknown (NULL), as the CSV writes it; a text that is no number is refused.
    if (row[i]->empty()) {
      row[i].reset();
    } else if (!valid_cell(type, *row[i])) {
      throw HistoryError("history table " + t.name + ", column " + t.columns[i].name + ": '" + *row[i] +
                         "' is not a valid value");
    }
  }
  queued_.emplace_back(&t, std::move(row));
}

std::size_t HistoryStore::commit() {
  if (queued_.empty()) return 0;
  const std::size_t stored = write(queued_);  // throws: the rows stay queued
  queued_.clear();
  return stored;
}

std::string url_problem(const std::string& url) {
  if (url.rfind("sqlite:", 0) == 0) return url.size() > 7 ? "" : "sqlite:PATH needs a file path";
  if (url.rfind("postgresql://", 0) == 0 || url.rfind("postgres://", 0) == 0) return "";
  return "'" + redact_url(url) + "' is no history URL: expected sqlite:PATH or postgresql://...";
}

std::unique_ptr<HistoryStore> open_history(const std::string& url) {
  if (const std::string problem = url_problem(url); !problem.empty()) throw HistoryError("history URL: " + problem);
  if (url.rfind("sqlite:", 0) == 0) return open_sqlite(url.substr(7));
  return open_postgres(url);
}

std::string redact_url(const std::string& url) {
  // postgresql://user:secret@host/db -> postgresql://user:***@host/db
  const auto scheme = url.find("://");
  const auto at = url.find('@');
  if (scheme == std::string::npos || at == std::string::npos) return url;
  const auto colon = url.find(':', scheme + 3);
  if (colon == std::string::npos || colon > at) return url;
  return url.substr(0, colon + 1) + "***" + url.substr(at);
}

}  // namespace causal::history
