#include "history_sink.hpp"

#include "causal/history/json_cells.hpp"
#include "causal/io/csv_format.hpp"
#include "causal/io/time_format.hpp"
#include "record_rows.hpp"

#include <spdlog/spdlog.h>

namespace causal::recorder {

namespace {
constexpr std::int64_t kRetentionEveryNs = 3600LL * 1'000'000'000LL;
}

history::Row condition_history_row(const causal_twin::ConditionVector& in) {
  const std::vector<std::string> csv = condition_row(in);  // snapshot,time_ns,time_utc,<values>
  std::vector<std::string> values(csv.begin() + 3, csv.end());
  return {in.asset_group(), in.feature(), csv[0], csv[1], csv[2],
          history::json_string_array(in.channel_names()), history::json_number_array(values)};
}

history::Row factor_history_row(const std::string& asset_group, const std::string& time_scale, const std::string& kind,
                                const std::vector<std::string>& header, const std::vector<std::string>& csv_row) {
  const std::vector<std::string> names(header.begin() + 3, header.end());
  const std::vector<std::string> values(csv_row.begin() + 3, csv_row.end());
  return {asset_group, time_scale, kind, csv_row[0], csv_row[1], csv_row[2], history::json_string_array(names),
          history::json_number_array(values)};
}

history::Row csv_history_row(const std::vector<std::string>& csv_row) {
  return history::Row(csv_row.begin(), csv_row.end());
}

void write_row(io::CsvFile& file, HistorySink* history, const char* table, const std::vector<std::string>& row,
               TopicCounts& counts) {
  file.write_row(row);
  if (history) history->add(table, csv_history_row(row));
  ++counts.written;
}

HistorySink::HistorySink(const std::string& url, double retention_days)
    : store_(history::open_history(url)), retention_days_(retention_days) {
  spdlog::info("history: {}{}", store_->describe(),
               retention_days_ > 0 ? " (rows older than " + std::to_string(retention_days_) + " days are deleted)" : "");
  if (retention_days_ > 0) {
    last_retention_ns_ = io::utc_now_ns();
    if (const auto n = store_->apply_retention(retention_days_, last_retention_ns_); n > 0) {
      spdlog::info("history: {} rows past the retention deleted", n);
    }
  }
}

void HistorySink::add(const char* table, history::Row row) {
  store_->add(table, std::move(row));
  ++added_;
}

void HistorySink::commit() {
  try {
    stored_ += store_->commit();
    if (failing_) spdlog::info("history: writing again ({} rows stored so far)", stored_);
    failing_ = false;
    if (retention_days_ > 0 && io::utc_now_ns() - last_retention_ns_ > kRetentionEveryNs) {
      last_retention_ns_ = io::utc_now_ns();
      store_->apply_retention(retention_days_, last_retention_ns_);
    }
  } catch (const history::HistoryError& e) {
    ++failed_commits_;
    if (!failing_) spdlog::error("history: {} ({} rows queued, retried with the next batch)", e.what(), store_->pending());
    failing_ = true;
  }
}

bool HistorySink::finish() {
  commit();
  const std::size_t unstored = store_->pending();
  spdlog::log(unstored == 0 ? spdlog::level::info : spdlog::level::err,
              "summary history={} rows={} new={} already_stored={} unstored={} failed_commits={}", store_->describe(),
              added_, stored_, added_ - stored_ - unstored, unstored, failed_commits_);
  return unstored == 0;
}

std::optional<std::int64_t> HistorySink::last_snapshot(const std::string& asset_group) {
  return store_->max_integer(history::table("condition_vectors"), "snapshot", asset_group);
}

}  // namespace causal::recorder
