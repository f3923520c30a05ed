// The historian's tables (docs/historian.md): the CSV columns of causal-recorder, typed, with a unique key and
// an (asset_group, time) index each. Condition vectors and factors have one column per channel or factor in
// their CSV files (a different set per asset group); here the names and values are JSON arrays, so one table
// holds every group.
#include "causal/history/history_store.hpp"

#include "causal/io/time_format.hpp"

#include <cerrno>
#include <cstdlib>

namespace causal::history {

namespace {

Column T(const char* n) { return {n, ColumnType::Text}; }
Column I(const char* n) { return {n, ColumnType::Integer}; }
Column R(const char* n) { return {n, ColumnType::Real}; }
Column B(const char* n) { return {n, ColumnType::Boolean}; }

std::vector<Table> make_tables() {
  std::vector<Table> t;
  t.push_back({"condition_vectors",
               {T("asset_group"), T("feature"), I("snapshot"), I("time_ns"), T("time_utc"), T("channel_names"),
                T("channel_values")},
               {"asset_group", "feature", "snapshot"},
               "time_ns"});
  t.push_back({"factors",
               {T("asset_group"), T("time_scale"), T("kind"), I("sample_index"), I("time_ns"), T("time_utc"),
                T("factor_names"), T("factor_values")},
               {"asset_group", "time_scale", "kind", "sample_index"},
               "time_ns"});
  t.push_back({"alarms",
               {T("alarm_id"), T("state"), T("severity"), T("kind"), T("asset_group"), I("channel"), T("channel_name"),
                I("sample_index"), T("time_utc"), T("raised_utc"), T("cleared_utc"), I("root_cause_channel"),
                T("root_cause_name"), R("score"), R("threshold"), T("reason"), T("category"),
                R("root_cause_confidence"), T("next_level"), R("hours_to_next_level"), R("hours_to_next_level_low"),
                R("hours_to_next_level_high")},
               {"asset_group", "alarm_id", "state", "severity", "sample_index"},
               "time_utc"});
  t.push_back({"recommendations",
               {T("recommendation_id"), T("alarm_id"), T("asset_group"), I("rank"), I("target_channel"),
                I("intervene_channel"), R("delta"), R("effect_immediate"), R("effect_steady_state"), R("effect_low"),
                R("effect_high"), R("confidence"), T("text"), T("answer_kind"), I("horizon_snapshots"),
                R("spectral_radius"), I("draws"), I("unstable_draws"), R("unstable_draw_share"), R("effect_median"),
                R("effect_percent"), R("effect_percent_low"), R("effect_percent_high"), R("effect_level_change"),
                B("reliable"), T("summary"), I("sample_index"), T("action"), T("action_kind"), I("act_on_channel"),
                T("act_on_name"), R("horizon_hours"), R("order_confidence"), T("order_source")},
               {"asset_group", "recommendation_id", "sample_index"},
               "sample_index"});
  t.push_back({"prognoses",
               {T("asset_group"), I("channel"), T("channel_name"), I("sample_index"), T("time_utc"), T("level"),
                R("hours"), R("hours_low"), R("hours_high"), B("known"), B("reached"), R("level_ratio"),
                R("current_ratio"), R("growth_per_hour"), R("coverage"), T("eta_utc"), T("eta_low_utc"),
                T("eta_high_utc"), T("alarm_id"), T("text")},
               {"asset_group", "channel", "level", "sample_index"},
               "time_utc"});
  t.push_back({"asset_status",
               {T("asset_group"), T("state"), I("learning_seen"), I("learning_needed"), I("sample_index"),
                T("time_utc"), B("has_alarm"), T("worst_severity"), I("open_alarms"), I("root_cause_channel"),
                T("root_cause_name"), T("action"), T("prognosis_text"), T("text"), I("unacknowledged_alarms"),
                I("shelved_alarms"), I("alarms_per_10_min"), B("alarm_flood"), I("standing_alarms"),
                I("chattering_alarms")},
               // The management counts are in the key: an acknowledgement republishes the line with them changed.
               {"asset_group", "sample_index", "state", "open_alarms", "text", "unacknowledged_alarms",
                "shelved_alarms", "alarms_per_10_min", "standing_alarms", "chattering_alarms"},
               "time_utc"});
  t.push_back({"alarm_actions",
               {T("action_id"), T("asset_group"), T("alarm_id"), T("action"), T("user_name"), T("reason"),
                T("time_utc"), T("until_utc"), I("time_ns"), I("until_ns")},
               {"asset_group", "action_id"},
               "time_utc"});
  // The closed loop: the columns of interventions.csv and intervention_outcomes.csv, one row per request id.
  // Their time column is the start snapshot (like recommendations: never deleted by --retention-days).
  t.push_back({"interventions",
               {T("request_id"), T("asset_group"), I("channel"), R("change_percent"), I("start_snapshot_index"),
                I("start_time_ns"), T("start_utc"), I("duration_snapshots"), T("recommendation_id"),
                I("target_channel"), T("approved_by"), I("approved_time_ns"), T("approved_utc")},
               {"asset_group", "request_id"},
               "start_snapshot_index"});
  t.push_back({"intervention_outcomes",
               {T("request_id"), T("asset_group"), T("recommendation_id"), I("channel"), I("target_channel"),
                I("start_snapshot_index"), I("end_snapshot_index"), T("status"), R("predicted_percent"),
                R("predicted_percent_low"), R("predicted_percent_high"), R("confidence"), R("observed_percent"),
                B("inside"), B("improved"), R("lever_trust"), B("lever_claimed"), T("text")},
               {"asset_group", "request_id"},
               "start_snapshot_index"});
  return t;
}

}  // namespace

std::size_t Table::column(const std::string& wanted) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i].name == wanted) return i;
  }
  return std::string::npos;
}

std::vector<std::string> Table::column_names() const {
  std::vector<std::string> out;
  for (const auto& c : columns) out.push_back(c.name);
  return out;
}

const std::vector<Table>& tables() {
  static const std::vector<Table> t = make_tables();
  return t;
}

const Table& table(const std::string& name) {
  for (const auto& t : tables()) {
    if (t.name == name) return t;
  }
  throw HistoryError("no history table '" + name + "'");
}

bool valid_cell(ColumnType type, const std::string& text) {
  if (type == ColumnType::Text) return true;
  if (type == ColumnType::Boolean) return text == "true" || text == "false";
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  if (type == ColumnType::Integer) {
    if (text[0] == '-') {
      (void)std::strtoll(text.c_str(), &end, 10);
    } else {
      (void)std::strtoull(text.c_str(), &end, 10);
    }
  } else {
    (void)std::strtod(text.c_str(), &end);
  }
  return errno == 0 && end != nullptr && *end == '\0';
}

namespace {
const char* sql_type(ColumnType t, bool postgres) {
  switch (t) {
    case ColumnType::Integer: return postgres ? "BIGINT" : "INTEGER";
    case ColumnType::Real: return postgres ? "DOUBLE PRECISION" : "REAL";
    case ColumnType::Boolean: return postgres ? "BOOLEAN" : "INTEGER";
    case ColumnType::Text: return "TEXT";
  }
  return "TEXT";
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}
}  // namespace

std::string create_table_sql(const Table& t, bool postgres) {
  std::string s = "CREATE TABLE IF NOT EXISTS " + t.name + " (";
  for (const auto& c : t.columns) s += c.name + " " + sql_type(c.type, postgres) + ", ";
  // Text key columns are never NULL (the CSV's empty cell is stored as ''), so the key is a real identity.
  return s + "PRIMARY KEY (" + joined(t.key) + "))";
}

std::vector<std::string> create_index_sql(const Table& t) {
  return {"CREATE INDEX IF NOT EXISTS " + t.name + "_group_time ON " + t.name + " (asset_group, " + t.time_column + ")"};
}

std::string insert_sql(const Table& t, bool postgres) {
  std::string s = "INSERT INTO " + t.name + " (" + joined(t.column_names()) + ") VALUES (";
  for (std::size_t i = 0; i < t.columns.size(); ++i) {
    s += i == 0 ? "" : ", ";
    s += postgres ? "$" + std::to_string(i + 1) : "?";
  }
  return s + ") ON CONFLICT DO NOTHING";
}

std::vector<std::string> create_schema_sql(bool postgres) {
  std::vector<std::string> out;
  for (const Table& t : tables()) {
    out.push_back(create_table_sql(t, postgres));
    for (auto& sql : create_index_sql(t)) out.push_back(std::move(sql));
  }
  return out;
}

namespace {

// Appends a parameter and returns its marker: "?" (SQLite) or "$n" (PostgreSQL).
std::string marker(BoundStatement& s, ColumnType type, std::string value, bool postgres) {
  s.values.emplace_back(type, std::move(value));
  return postgres ? "$" + std::to_string(s.values.size()) : "?";
}

// A time bound as the table's time column spells it.
std::pair<ColumnType, std::string> time_bound(const Table& t, std::int64_t ns) {
  if (t.time_column == "time_utc") return {ColumnType::Text, io::format_utc(ns)};
  return {ColumnType::Integer, std::to_string(ns)};
}

}  // namespace

BoundStatement select_sql(const Table& t, const RangeQuery& q, bool postgres) {
  BoundStatement s;
  s.sql = "SELECT " + joined(t.column_names()) + " FROM " + t.name + " WHERE 1=1";
  if (!q.asset_group.empty()) s.sql += " AND asset_group = " + marker(s, ColumnType::Text, q.asset_group, postgres);
  for (const auto& [bound, op] : {std::pair{q.from_ns, " >= "}, std::pair{q.to_ns, " <= "}}) {
    if (!bound) continue;
    auto [type, text] = time_bound(t, *bound);
    s.sql += " AND " + t.time_column + op + marker(s, type, std::move(text), postgres);
  }
  s.sql += " ORDER BY " + t.time_column;
  for (const auto& k : t.key) s.sql += ", " + k;
  if (q.limit > 0) s.sql += " LIMIT " + std::to_string(q.limit);
  return s;
}

std::vector<BoundStatement> retention_sql(double days, std::int64_t now_ns, bool postgres) {
  std::vector<BoundStatement> out;
  if (!(days > 0)) return out;
  const auto cutoff = now_ns - static_cast<std::int64_t>(days * 86400.0 * 1e9);
  for (const Table& t : tables()) {
    if (t.time_column != "time_utc" && t.time_column != "time_ns") continue;
    BoundStatement s;
    auto [type, text] = time_bound(t, cutoff);
    s.sql = "DELETE FROM " + t.name + " WHERE " + t.time_column + " < " + marker(s, type, std::move(text), postgres) +
            (t.time_column == "time_utc" ? " AND time_utc <> ''" : "");
    out.push_back(std::move(s));
  }
  return out;
}

BoundStatement max_integer_sql(const Table& t, const std::string& column, const std::string& asset_group,
                               bool postgres) {
  if (t.column(column) == std::string::npos) throw HistoryError("no column " + column + " in " + t.name);
  BoundStatement s;
  s.sql = "SELECT MAX(" + column + ") FROM " + t.name +
          " WHERE asset_group = " + marker(s, ColumnType::Text, asset_group, postgres);
  return s;
}

std::string earliest_sql(const Table& t) {
  return "SELECT MIN(" + t.time_column + ") FROM " + t.name +
         (t.time_column == "time_utc" ? " WHERE time_utc <> ''" : "");
}

}  // namespace causal::history
