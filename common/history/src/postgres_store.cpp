// PostgreSQL backend (libpq): one history for many hosts. Statements are prepared once per connection; cells
// travel as text parameters and the server converts them to the column types. Creating the schema takes a
// transaction-level advisory lock, so two services starting together do not race on CREATE TABLE.
#include "backends.hpp"

#include "causal/io/time_format.hpp"

#ifdef CAUSAL_HISTORY_HAVE_LIBPQ
#include <libpq-fe.h>
#endif

#include <map>

namespace causal::history {

#ifndef CAUSAL_HISTORY_HAVE_LIBPQ
std::unique_ptr<HistoryStore> open_postgres(const std::string& url) {
  throw HistoryError("history URL '" + redact_url(url) + "': this build has no PostgreSQL client (libpq)");
}
#else
namespace {

class Result {
 public:
  explicit Result(PGresult* r) : r_(r) {}
  ~Result() { PQclear(r_); }
  Result(const Result&) = delete;
  Result& operator=(const Result&) = delete;
  PGresult* get() const { return r_; }
  PGresult* release() {
    PGresult* r = r_;
    r_ = nullptr;
    return r;
  }

 private:
  PGresult* r_;
};

class PostgresStore final : public HistoryStore {
 public:
  explicit PostgresStore(const std::string& url) : url_(redact_url(url)) {
    conn_ = PQconnectdb(url.c_str());
    if (conn_ == nullptr || PQstatus(conn_) != CONNECTION_OK) {
      const std::string why = conn_ ? PQerrorMessage(conn_) : "out of memory";
      PQfinish(conn_);
      throw HistoryError("cannot open history " + url_ + ": " + why);
    }
    exec("SET client_min_messages = warning");  // "relation already exists, skipping" is not news
    exec("BEGIN");
    exec("SELECT pg_advisory_xact_lock(7301)");
    for (const auto& sql : create_schema_sql(true)) exec(sql);
    exec("COMMIT");
  }
  ~PostgresStore() override { PQfinish(conn_); }

  std::string describe() const override { return url_; }

  std::size_t apply_retention(double days, std::int64_t now_ns) override {
    const auto deletes = retention_sql(days, now_ns, true);
    if (deletes.empty()) return 0;
    return in_transaction(deletes, [&](const BoundStatement& d) { return changed(params(d, PGRES_COMMAND_OK)); });
  }

  std::vector<Row> select(const Table& t, const RangeQuery& q) override {
    Result r = params(select_sql(t, q, true), PGRES_TUPLES_OK);
    std::vector<Row> rows;
    const int n = PQntuples(r.get());
    for (int i = 0; i < n; ++i) {
      Row row;
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        const int col = static_cast<int>(c);
        if (PQgetisnull(r.get(), i, col)) {
          row.emplace_back();
          continue;
        }
        std::string v = PQgetvalue(r.get(), i, col);
        if (t.columns[c].type == ColumnType::Boolean) v = v == "t" ? "true" : "false";
        row.emplace_back(std::move(v));
      }
      rows.push_back(std::move(row));
    }
    return rows;
  }

  std::optional<std::int64_t> max_integer(const Table& t, const std::string& column,
                                          const std::string& asset_group) override {
    Result r = params(max_integer_sql(t, column, asset_group, true), PGRES_TUPLES_OK);
    if (PQntuples(r.get()) == 0 || PQgetisnull(r.get(), 0, 0)) return std::nullopt;
    return std::stoll(PQgetvalue(r.get(), 0, 0));
  }

  std::uint64_t count(const Table& t) override {
    Result r = params("SELECT COUNT(*) FROM " + t.name, {}, PGRES_TUPLES_OK);
    return std::stoull(PQgetvalue(r.get(), 0, 0));
  }

  std::optional<std::int64_t> earliest(const Table& t) override {
    Result r = params(earliest_sql(t), {}, PGRES_TUPLES_OK);
    if (PQntuples(r.get()) == 0 || PQgetisnull(r.get(), 0, 0)) return std::nullopt;
    const std::string v = PQgetvalue(r.get(), 0, 0);
    if (t.time_column != "time_utc") return std::stoll(v);
    return io::parse_utc(v);
  }

 protected:
  std::size_t write(const std::vector<std::pair<const Table*, Row>>& rows) override {
    return in_transaction(rows, [&](const std::pair<const Table*, Row>& table_row) {
      const auto& [t, row] = table_row;
      const std::string name = "insert_" + t->name;
      if (!prepared_.count(name)) {
        Result p(PQprepare(conn_, name.c_str(), insert_sql(*t, true).c_str(), 0, nullptr));
        check(p, PGRES_COMMAND_OK, "prepare " + name);
        prepared_[name] = true;
      }
      std::vector<const char*> values;
      for (const auto& cell : row) values.push_back(cell ? cell->c_str() : nullptr);
      Result r(PQexecPrepared(conn_, name.c_str(), static_cast<int>(values.size()), values.data(), nullptr, nullptr, 0));
      check(r, PGRES_COMMAND_OK, name);
      return changed(r);
    });
  }

 private:
  template <class Items, class Run>
  std::size_t in_transaction(const Items& items, Run run) {
    return sum_in_transaction(
        items, "BEGIN", [&](const char* sql) { exec(sql); }, [&] { Result rollback(PQexec(conn_, "ROLLBACK")); }, run);
  }
  // Rows a command changed.
  static std::size_t changed(const Result& r) { return std::stoul("0" + std::string(PQcmdTuples(r.get()))); }
  void check(const Result& r, ExecStatusType want, const std::string& what) {
    if (PQresultStatus(r.get()) != want) {
      throw HistoryError("postgresql " + url_ + ": " + PQerrorMessage(conn_) + " in: " + what);
    }
  }
  void exec(const std::string& sql) {
    Result r(PQexec(conn_, sql.c_str()));
    const auto status = PQresultStatus(r.get());
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) check(r, PGRES_COMMAND_OK, sql);
  }
  Result params(const BoundStatement& s, ExecStatusType want) {
    std::vector<std::string> values;
    for (const auto& [type, text] : s.values) values.push_back(text);
    return params(s.sql, values, want);
  }
  Result params(const std::string& sql, const std::vector<std::string>& values, ExecStatusType want) {
    std::vector<const char*> v;
    for (const auto& s : values) v.push_back(s.c_str());
    Result r(PQexecParams(conn_, sql.c_str(), static_cast<int>(v.size()), nullptr, v.data(), nullptr, nullptr, 0));
    check(r, want, sql);
    return Result(r.release());
  }

  std::string url_;
  PGconn* conn_ = nullptr;
  std::map<std::string, bool> prepared_;
};

}  // namespace

std::unique_ptr<HistoryStore> open_postgres(const std::string& url) { return std::make_unique<PostgresStore>(url); }
#endif

}  // namespace causal::history
