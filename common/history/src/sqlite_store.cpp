// SQLite backend: one file, WAL journal (readers such as twin-web do not block the recorder's writer, and a
// committed transaction survives a kill -9 of the writing process), synchronous=NORMAL (durable across a process
// crash; the last transactions may be lost only on a power cut of the host).
#include "backends.hpp"

#include "causal/io/time_format.hpp"

#include <sqlite3.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace causal::history {

namespace {

std::string format_real(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
      throw HistoryError("sqlite: " + std::string(sqlite3_errmsg(db)) + " in: " + sql);
    }
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  sqlite3_stmt* get() { return stmt_; }
  // SQLITE_ROW or SQLITE_DONE; anything else throws.
  int step() {
    const int rc = sqlite3_step(stmt_);
    if (rc != SQLITE_ROW && rc != SQLITE_DONE) throw HistoryError("sqlite: " + std::string(sqlite3_errmsg(db_)));
    return rc;
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

void bind(sqlite3_stmt* s, int i, ColumnType type, const Cell& cell) {
  if (!cell) {
    sqlite3_bind_null(s, i);
    return;
  }
  switch (type) {
    case ColumnType::Integer: sqlite3_bind_int64(s, i, std::stoll(*cell)); break;
    case ColumnType::Real: sqlite3_bind_double(s, i, std::stod(*cell)); break;  // NaN is stored as NULL by SQLite
    case ColumnType::Boolean: sqlite3_bind_int(s, i, *cell == "true" ? 1 : 0); break;
    case ColumnType::Text: sqlite3_bind_text(s, i, cell->c_str(), static_cast<int>(cell->size()), SQLITE_TRANSIENT); break;
  }
}

void bind_values(Statement& s, const BoundStatement& b) {
  int i = 1;
  for (const auto& [type, text] : b.values) bind(s.get(), i++, type, text);
}

Cell read_cell(sqlite3_stmt* s, int i, ColumnType type) {
  if (sqlite3_column_type(s, i) == SQLITE_NULL) return std::nullopt;
  switch (type) {
    case ColumnType::Integer: return std::to_string(sqlite3_column_int64(s, i));
    case ColumnType::Real: return format_real(sqlite3_column_double(s, i));
    case ColumnType::Boolean: return std::string(sqlite3_column_int(s, i) != 0 ? "true" : "false");
    case ColumnType::Text: break;
  }
  const unsigned char* text = sqlite3_column_text(s, i);
  return std::string(reinterpret_cast<const char*>(text), static_cast<std::size_t>(sqlite3_column_bytes(s, i)));
}

class SqliteStore final : public HistoryStore {
 public:
  explicit SqliteStore(std::string path) : path_(std::move(path)) {
    const auto parent = std::filesystem::path(path_).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    if (sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
      const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw HistoryError("cannot open history " + path_ + ": " + why);
    }
    sqlite3_busy_timeout(db_, 10000);  // a reader's snapshot or another writer: wait, do not fail
    exec("PRAGMA journal_mode=WAL");
    exec("PRAGMA synchronous=NORMAL");
    exec("BEGIN");
    for (const auto& sql : create_schema_sql(false)) exec(sql);
    exec("COMMIT");
  }
  ~SqliteStore() override {
    inserts_.clear();
    sqlite3_close(db_);
  }

  std::string describe() const override { return "sqlite:" + path_; }

  std::size_t apply_retention(double days, std::int64_t now_ns) override {
    const auto deletes = retention_sql(days, now_ns, false);
    if (deletes.empty()) return 0;
    return in_transaction(deletes, [&](const BoundStatement& d) {
      Statement s(db_, d.sql);
      bind_values(s, d);
      s.step();
      return static_cast<std::size_t>(sqlite3_changes(db_));
    });
  }

  std::vector<Row> select(const Table& t, const RangeQuery& q) override {
    const BoundStatement query = select_sql(t, q, false);
    Statement s(db_, query.sql);
    bind_values(s, query);
    std::vector<Row> rows;
    while (s.step() == SQLITE_ROW) {
      Row r;
      for (std::size_t i = 0; i < t.columns.size(); ++i) r.push_back(read_cell(s.get(), static_cast<int>(i), t.columns[i].type));
      rows.push_back(std::move(r));
    }
    return rows;
  }

  std::optional<std::int64_t> max_integer(const Table& t, const std::string& column,
                                          const std::string& asset_group) override {
    const BoundStatement query = max_integer_sql(t, column, asset_group, false);
    Statement s(db_, query.sql);
    bind_values(s, query);
    if (s.step() != SQLITE_ROW || sqlite3_column_type(s.get(), 0) == SQLITE_NULL) return std::nullopt;
    return sqlite3_column_int64(s.get(), 0);
  }

  std::uint64_t count(const Table& t) override {
    Statement s(db_, "SELECT COUNT(*) FROM " + t.name);
    s.step();
    return static_cast<std::uint64_t>(sqlite3_column_int64(s.get(), 0));
  }

  std::optional<std::int64_t> earliest(const Table& t) override {
    Statement s(db_, earliest_sql(t));
    if (s.step() != SQLITE_ROW || sqlite3_column_type(s.get(), 0) == SQLITE_NULL) return std::nullopt;
    if (t.time_column != "time_utc") return sqlite3_column_int64(s.get(), 0);
    return io::parse_utc(reinterpret_cast<const char*>(sqlite3_column_text(s.get(), 0)));
  }

 protected:
  std::size_t write(const std::vector<std::pair<const Table*, Row>>& rows) override {
    return in_transaction(rows, [&](const std::pair<const Table*, Row>& table_row) {
      const auto& [t, row] = table_row;
      auto it = inserts_.find(t->name);
      if (it == inserts_.end()) it = inserts_.emplace(t->name, std::make_unique<Statement>(db_, insert_sql(*t, false))).first;
      Statement& s = *it->second;
      for (std::size_t i = 0; i < row.size(); ++i) bind(s.get(), static_cast<int>(i + 1), t->columns[i].type, row[i]);
      s.step();
      const auto stored = static_cast<std::size_t>(sqlite3_changes(db_));
      s.reset();
      return stored;
    });
  }

 private:
  // BEGIN IMMEDIATE: the write lock at once, so a concurrent writer waits at BEGIN rather than failing mid-way.
  template <class Items, class Run>
  std::size_t in_transaction(const Items& items, Run run) {
    return sum_in_transaction(
        items, "BEGIN IMMEDIATE", [&](const char* sql) { exec(sql); },
        [&] {
          sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
          for (auto& [name, s] : inserts_) s->reset();
        },
        run);
  }
  void exec(const std::string& sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string why = err ? err : "?";
      sqlite3_free(err);
      throw HistoryError("sqlite " + path_ + ": " + why + " in: " + sql);
    }
  }

  std::string path_;
  sqlite3* db_ = nullptr;
  std::map<std::string, std::unique_ptr<Statement>> inserts_;
};

}  // namespace

std::unique_ptr<HistoryStore> open_sqlite(const std::string& path) { return std::make_unique<SqliteStore>(path); }

}  // namespace causal::history
