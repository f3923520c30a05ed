// The twin's history in a database: the tables of docs/historian.md (condition vectors, condition-level factors,
// alarm events, recommendations, prognoses, asset status, alarm actions, interventions and their outcomes), one
// interface and two backends: SQLite (an embedded file, WAL journal; the default) and PostgreSQL (libpq; one
// history for many hosts).
// causal-recorder writes it, twin-web and the tests read it. Cells travel as the CSV spells them (nullopt =
// NULL); each backend stores them typed by the table's column types. Every table has a unique key, so a
// replayed or re-delivered row is stored once (INSERT ... ON CONFLICT DO NOTHING), and rows are written in
// batches, one transaction per commit().
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace causal::history {

// Thrown for a bad URL, a database that cannot be opened, or a statement the database refused.
class HistoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ColumnType { Integer, Real, Boolean, Text };

struct Column {
  std::string name;
  ColumnType type = ColumnType::Text;
};

struct Table {
  std::string name;
  std::vector<Column> columns;
  std::vector<std::string> key;  // unique: the identity of a row (a repeat is not stored again)
  std::string time_column;       // indexed together with asset_group; "time_ns" (integer) or "time_utc" (text)
  // Index of a column by name, or npos.
  std::size_t column(const std::string& name) const;
  std::vector<std::string> column_names() const;
};

// The nine tables, in the order of docs/historian.md.
const std::vector<Table>& tables();
// A table by name; throws HistoryError for an unknown name.
const Table& table(const std::string& name);

using Cell = std::optional<std::string>;
using Row = std::vector<Cell>;  // one cell per column of its table, in column order

// Rows of one table, optionally of one asset group and within [from_ns, to_ns] of the table's time column
// (inclusive; a time_utc table compares the UTC text), ordered by time and then by key.
struct RangeQuery {
  std::string asset_group;  // "" = every group
  std::optional<std::int64_t> from_ns, to_ns;
  std::size_t limit = 0;  // 0 = no limit
};

class HistoryStore {
 public:
  virtual ~HistoryStore() = default;
  HistoryStore() = default;
  HistoryStore(const HistoryStore&) = delete;
  HistoryStore& operator=(const HistoryStore&) = delete;

  // "sqlite:/path/history.db" or "postgresql://host/db" (the password left out).
  virtual std::string describe() const = 0;

  // Queues a row for the next commit(); throws HistoryError when the cell count is not the table's.
  void add(const std::string& table_name, Row row);
  std::size_t pending() const { return queued_.size(); }
  // Writes every queued row in one transaction. Returns the rows newly stored; the others were there already.
  // On failure the rows stay queued (a later commit retries them) and HistoryError is thrown.
  std::size_t commit();

  // Deletes rows whose time is before now_ns - days (days > 0); returns how many.
  virtual std::size_t apply_retention(double days, std::int64_t now_ns) = 0;
  virtual std::vector<Row> select(const Table& t, const RangeQuery& q) = 0;
  // MAX(column) over the rows of one asset group (an integer column), nullopt when there are none.
  virtual std::optional<std::int64_t> max_integer(const Table& t, const std::string& column,
                                                  const std::string& asset_group) = 0;
  virtual std::uint64_t count(const Table& t) = 0;
  // MIN of the table's time column in ns (time_utc tables: parsed), nullopt when empty.
  virtual std::optional<std::int64_t> earliest(const Table& t) = 0;

 protected:
  // One transaction; returns rows newly stored.
  virtual std::size_t write(const std::vector<std::pair<const Table*, Row>>& rows) = 0;

 private:
  std::vector<std::pair<const Table*, Row>> queued_;
};

// Opens (and creates: tables, indices) the history named by url: "sqlite:PATH" (a file, created with its
// folder) or "postgresql://..." / "postgres://..." (a libpq connection URI). Throws HistoryError.
std::unique_ptr<HistoryStore> open_history(const std::string& url);
// "" when url names a backend (sqlite:PATH with a path, postgresql:// or postgres://), else why not: for the
// command lines, which refuse a bad --db as a usage error before anything starts.
std::string url_problem(const std::string& url);

// The SQL text of one cell as the CSV spells it: "true"/"false" for Boolean, numbers as written.
// Integer and Real cells that do not parse are refused by add() (HistoryError naming the column).
bool valid_cell(ColumnType type, const std::string& text);

// Statements shared by the backends (parameter markers: "?" for SQLite, "$n" for PostgreSQL).
std::string create_table_sql(const Table& t, bool postgres);
std::vector<std::string> create_index_sql(const Table& t);
std::string insert_sql(const Table& t, bool postgres);
// Every CREATE TABLE and CREATE INDEX of tables(), in order (each backend runs them in one transaction).
std::vector<std::string> create_schema_sql(bool postgres);

// A statement and the SQL text of its parameters, each typed as the column it is compared with (SQLite binds
// by type; PostgreSQL infers it from the column).
struct BoundStatement {
  std::string sql;
  std::vector<std::pair<ColumnType, std::string>> values;
};
// The SELECT of RangeQuery q on t: its columns in order, ordered by time and then by key.
BoundStatement select_sql(const Table& t, const RangeQuery& q, bool postgres);
// apply_retention's DELETEs: one per table with a time of its own (recommendations have none: they are kept with
// their alarms), of the rows before now_ns - days (a time_utc table compares the UTC text and keeps rows
// without a time).
std::vector<BoundStatement> retention_sql(double days, std::int64_t now_ns, bool postgres);
// max_integer's SELECT: the largest `column` (HistoryError unless t has it) among asset_group's rows.
BoundStatement max_integer_sql(const Table& t, const std::string& column, const std::string& asset_group,
                               bool postgres);
// earliest's SELECT: the smallest time of t (a time_utc table leaves out the rows without a time).
std::string earliest_sql(const Table& t);

}  // namespace causal::history
