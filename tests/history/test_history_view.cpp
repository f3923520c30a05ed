// twin-web's history (--db): rows of a real SQLite history become the live view's state (history_loader) and
// /api/history answers ranges (history_routes). One field list per recorded message (causal/dds/message_fields.hpp)
// serves both sides: causal-recorder's header is the table's column list, and a message it writes comes back from
// twin-web's reader with every recorded field equal. Alarm events come back in the order they happened even when an
// escalation's time is unknown; an index gap stays a gap in the trend; a bad range parameter is refused by name.
#include "history_cells.hpp"
#include "history_loader.hpp"
#include "history_routes.hpp"
#include "history_sink.hpp"
#include "row_cells.hpp"

#include "causal/dds/message_fields.hpp"
#include "causal/history/history_store.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;
using causal::history::Row;

namespace {

class HistoryView : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("causal-history-view-" + std::to_string(getpid()));
    fs::remove_all(dir_);
    store_ = causal::history::open_history("sqlite:" + (dir_ / "history.db").string());
    // Snapshots 0, 1, 2 and 5, 6 (3 and 4 never came: a gap), one hour apart from 2004-02-12 10:00:00.
    for (int i : {0, 1, 2, 5, 6}) {
      const long long t = (1076580000LL + 3600LL * i) * 1'000'000'000LL;
      store_->add("condition_vectors", Row{"pump-7", "meanabs", std::to_string(i), std::to_string(t), "",
                                           "[\"drive\",\"pump\"]", "[1.5," + std::to_string(2 + i) + "]"});
    }
    store_->add("alarms", alarm("raised", "warning", "1", "2004-02-12 11:00:00", "2004-02-12 11:00:00", ""));
    // An escalation whose data time the recorder did not know (empty time_utc): sorts first by time.
    store_->add("alarms", alarm("escalated", "critical", "2", "", "2004-02-12 11:00:00", ""));
    store_->add("alarms", alarm("cleared", "critical", "6", "2004-02-12 16:00:00", "2004-02-12 11:00:00",
                                "2004-02-12 16:00:00"));
    ASSERT_EQ(store_->commit(), 8u);
  }
  void TearDown() override {
    store_.reset();
    fs::remove_all(dir_);
  }
  static Row alarm(const char* state, const char* severity, const char* index, const char* time, const char* raised,
                   const char* cleared) {
    const auto& t = causal::history::table("alarms");
    Row r(t.columns.size(), std::string());
    auto set = [&](const char* name, const std::string& v) { r[t.column(name)] = v; };
    set("alarm_id", "pump-7/2/cusum/1");
    set("state", state);
    set("severity", severity);
    set("kind", "cusum");
    set("asset_group", "pump-7");
    set("channel", "2");
    set("channel_name", "pump");
    set("sample_index", index);
    set("time_utc", time);
    set("raised_utc", raised);
    set("cleared_utc", cleared);
    set("root_cause_channel", "1");
    set("category", "degradation");
    return r;
  }
  // Written as causal-recorder writes it, read back as twin-web reads it (the message's own asset group: the
  // fixture's rows are in the same tables).
  template <class Message>
  void expect_round_trip(const Message& m, causal::web::RowFields::Integers integers) {
    const char* table = causal::dds::MessageFields<Message>::table;
    EXPECT_EQ(causal::recorder::header_of<Message>(), causal::history::table(table).column_names()) << table;
    store_->add(table, causal::recorder::csv_history_row(causal::recorder::row_of(m)));
    ASSERT_EQ(store_->commit(), 1u) << table;
    causal::history::RangeQuery q;
    q.asset_group = m.asset_group();
    const auto rows = store_->select(causal::history::table(table), q);
    ASSERT_EQ(rows.size(), 1u) << table;
    const auto back = causal::web::message_from_row<Message>(rows[0], integers);
    ASSERT_TRUE(back.has_value()) << table;
    EXPECT_EQ(causal::recorder::row_of(*back), causal::recorder::row_of(m)) << table;
  }
  fs::path dir_;
  std::unique_ptr<causal::history::HistoryStore> store_;
};

TEST_F(HistoryView, TheWholeHistoryBecomesTheLiveViewsState) {
  causal::web::TwinState state;
  const auto load = causal::web::load_history(*store_, state, {});
  EXPECT_EQ(load.condition_vectors, 5u);
  EXPECT_EQ(load.alarm_events, 3u);
  EXPECT_EQ(load.unreadable, 0u);
  ASSERT_TRUE(load.earliest_ns.has_value());
  EXPECT_EQ(*load.earliest_ns, 1076580000LL * 1'000'000'000LL);
  const auto g = state.group("pump-7");
  ASSERT_TRUE(g.has_value());
  ASSERT_EQ(g->trend.size(), 5u);
  EXPECT_EQ(g->trend[3].index, 5u);  // the gap is kept: no invented points for 3 and 4
  EXPECT_DOUBLE_EQ(g->trend[4].values[1], 8.0);
  ASSERT_EQ(g->alarms.size(), 1u);
  const auto& a = g->alarms.begin()->second;
  EXPECT_EQ(a.last.state(), causal_twin::CLEARED);  // raise, escalation, clear: in the order they happened
  EXPECT_EQ(a.last.severity(), causal_twin::CRITICAL);
  EXPECT_EQ(a.raised_index, 1u);
}

TEST_F(HistoryView, ARangeComesFromTheDatabaseAndBadParametersAreRefusedByName) {
  causal::web::HistoryRoutes routes(store_.get(), 2000);
  const auto reply = routes.range("pump-7", "2004-02-12T11:00:00Z", "2004-02-12 15:00:00");
  ASSERT_EQ(reply.status, 200) << reply.body;
  const auto body = nlohmann::json::parse(reply.body);
  EXPECT_EQ(body["group"]["trend"]["index"], nlohmann::json::array({1, 2, 5}));
  EXPECT_EQ(routes.range("pump-7", "yesterday", "").status, 400);
  EXPECT_NE(routes.range("pump-7", "", "noon").body.find("to:"), std::string::npos);
  EXPECT_EQ(routes.range("", "", "").status, 400);
  EXPECT_EQ(routes.range("pump-7", "2004-02-13", "2004-02-12").status, 400);
  causal::web::HistoryRoutes none(nullptr, 0);
  EXPECT_EQ(none.range("pump-7", "", "").status, 404);
}

// Gives every listed field its own value (text: its column name; numbers: the column's position), so a column
// read into the wrong field, or not read, shows in the row written again.
class FillFields {
 public:
  void text(const char* name, std::string& s) { s = std::string(name) + " " + std::to_string(++n_); }
  template <class T>
  void integer(const char*, T& v) { v = static_cast<T>(++n_ * 7); }
  void real(const char*, double& v) { v = ++n_ + 0.25; }
  void hours(const char*, double& v, bool) { v = ++n_ + 0.5; }
  void flag(const char*, bool& b) { b = (++n_ % 2) == 1; }
  // 2004-02-12 10:32:39 UTC plus whole seconds (the UTC text keeps seconds).
  void utc(const char*, std::int64_t& ns) { ns = (1076581959LL + ++n_) * 1'000'000'000LL; }
  template <class E>
  void named(const char*, E& e, bool = true) { e = static_cast<E>(++n_ % 3); }
  void utc_copy(const char*, std::int64_t) {}
  void derived(const char*, const std::string&) {}

 private:
  int n_ = 0;
};

template <class Message>
Message filled() {
  Message m;
  FillFields fill;
  causal::dds::MessageFields<Message>::list(fill, m);
  return m;
}


TEST_F(HistoryView, EveryRecordedFieldComesBackFromTheHistory) {
  using Integers = causal::web::RowFields::Integers;
  expect_round_trip(filled<causal_twin::Alarm>(), Integers::ZeroWhenEmpty);
  expect_round_trip(filled<causal_twin::Recommendation>(), Integers::ZeroWhenEmpty);
  expect_round_trip(filled<causal_twin::Prognosis>(), Integers::ZeroWhenEmpty);
  expect_round_trip(filled<causal_twin::AssetStatus>(), Integers::ZeroWhenEmpty);
  expect_round_trip(filled<causal_twin::Intervention>(), Integers::Required);
  expect_round_trip(filled<causal_twin::InterventionOutcome>(), Integers::Required);
  // Alarm actions are written, not read back by twin-web: their header is the table's all the same.
  EXPECT_EQ(causal::recorder::header_of<causal_twin::AlarmActionResult>(),
            causal::history::table("alarm_actions").column_names());
}

TEST_F(HistoryView, UnknownHoursAndNoOpenAlarmStayUnknown) {
  auto a = filled<causal_twin::Alarm>();
  a.next_level("");  // no level ahead: the hours are not written, and read back as unknown
  const auto row = causal::recorder::row_of(a);
  EXPECT_EQ(row[19], "");
  auto s = filled<causal_twin::AssetStatus>();
  s.has_alarm(false);  // no open alarm: no worst severity
  const auto status_row = causal::recorder::row_of(s);
  EXPECT_EQ(status_row[7], "");
  store_->add("alarms", causal::recorder::csv_history_row(row));
  store_->add("asset_status", causal::recorder::csv_history_row(status_row));
  ASSERT_EQ(store_->commit(), 2u);
  causal::history::RangeQuery q;
  q.asset_group = a.asset_group();
  const auto alarm = causal::web::alarm_from_row(store_->select(causal::history::table("alarms"), q).at(0));
  ASSERT_TRUE(alarm.has_value());
  EXPECT_TRUE(std::isnan(alarm->hours_to_next_level()));
  q.asset_group = s.asset_group();
  const auto status = causal::web::status_from_row(store_->select(causal::history::table("asset_status"), q).at(0));
  ASSERT_TRUE(status.has_value());
  EXPECT_FALSE(status->has_alarm());
  EXPECT_EQ(status->worst_severity(), causal_twin::Severity{});
}

}  // namespace
