// causal-recorder's database output (--db): the rows it writes to its CSV files, also in the historian's tables
// (common/history, docs/historian.md), committed once per batch in one transaction. A row the database already
// has (a replay after a restart, a re-delivery) is stored once: the tables are keyed. A commit that fails keeps
// its rows queued and is retried with the next batch; rows still unstored at exit are counted and make the exit
// code 4 (an incomplete history).
#pragma once

#include "record_rows.hpp"

#include "causal/history/history_store.hpp"
#include "causal/io/csv_format.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace causal::recorder {

// condition_vectors: asset_group, feature, snapshot, time_ns, time_utc, channel_names, channel_values (JSON).
history::Row condition_history_row(const causal_twin::ConditionVector& in);
// factors: asset_group, time_scale, kind, then the CSV row (index,time_ns,time_utc,<factor columns...>) with the
// factor columns as two JSON arrays (names from the header, values from the row).
history::Row factor_history_row(const std::string& asset_group, const std::string& time_scale, const std::string& kind,
                                const std::vector<std::string>& header, const std::vector<std::string>& csv_row);
// The other tables have the CSV's columns exactly: every cell as written.
history::Row csv_history_row(const std::vector<std::string>& csv_row);

class HistorySink;
// One row written: to its CSV file and, with --db (history not null), to `table` (its columns are the file's);
// counted in counts.written.
void write_row(io::CsvFile& file, HistorySink* history, const char* table, const std::vector<std::string>& row,
               TopicCounts& counts);

class HistorySink {
 public:
  // Opens (creates) the history; throws history::HistoryError. retention_days > 0: rows older than that many days
  // (of data time, against the wall clock) are deleted at start and once an hour.
  HistorySink(const std::string& url, double retention_days);
  void add(const char* table, history::Row row);
  // Commits the batch; logs (once per failure streak) and keeps the rows when the database refuses.
  void commit();
  // Last commit; logs the summary. True when every row reached the database.
  bool finish();
  // Newest snapshot stored for a group's condition vectors (what a restarted recorder resumes after).
  std::optional<std::int64_t> last_snapshot(const std::string& asset_group);

 private:
  std::unique_ptr<history::HistoryStore> store_;
  double retention_days_ = 0.0;
  std::int64_t last_retention_ns_ = 0;
  std::uint64_t added_ = 0, stored_ = 0, failed_commits_ = 0;
  bool failing_ = false;
};

}  // namespace causal::recorder
