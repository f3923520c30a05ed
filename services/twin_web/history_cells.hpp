// Typed access to one historian row by column name, for turning rows back into the messages they were written
// from (history_loader, history_interventions). A missing column or an unparsable number throws; guarded() turns
// that into nullopt, so a row that does not convert is counted unreadable, never shown half.
#pragma once

#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/message_fields.hpp"
#include "causal/history/history_store.hpp"
#include "causal/io/time_format.hpp"

#include <cmath>
#include <cstdint>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace causal::web {

class HistoryCells {
 public:
  HistoryCells(const char* table, const history::Row& row) : t_(history::table(table)), r_(row) {}
  std::string text(const char* name) const { return cell(name).value_or(""); }
  double real(const char* name) const {
    const auto& c = cell(name);
    return c && !c->empty() ? std::stod(*c) : NAN;  // NULL: unknown (NaN, as on the topic)
  }
  // NULL or empty reads as 0 (not set, as on the topic).
  std::int64_t integer(const char* name) const {
    const auto& c = cell(name);
    return c && !c->empty() ? std::stoll(*c) : 0;
  }
  // For columns the writer always fills: NULL or empty makes the row unreadable.
  std::int64_t required_integer(const char* name) const {
    const auto& c = cell(name);
    if (!c || c->empty()) throw std::invalid_argument(std::string("no value in ") + name);
    return std::stoll(*c);
  }
  bool boolean(const char* name) const { return cell(name).value_or("") == "true"; }
  // A UTC text column as ns since the epoch; NULL or empty is 0 (not set, as on the topic).
  std::int64_t utc(const char* name) const {
    const auto& c = cell(name);
    if (!c || c->empty()) return 0;
    const auto ns = io::parse_utc(*c);
    if (!ns) throw std::invalid_argument(std::string("bad time in ") + name);
    return *ns;
  }

 private:
  const history::Cell& cell(const char* name) const {
    const std::size_t i = t_.column(name);
    if (i == std::string::npos || i >= r_.size()) throw std::invalid_argument(std::string("no column ") + name);
    return r_[i];
  }
  const history::Table& t_;
  const history::Row& r_;
};

// The enum value whose name (dds::to_string) is `name`; the IDL enums have 3 values each.
template <typename E>
E enum_named(const std::string& name) {
  for (int i = 0; i < 3; ++i) {
    if (name == dds::to_string(static_cast<E>(i), "?")) return static_cast<E>(i);
  }
  throw std::invalid_argument("unknown value " + name);
}

// twin-web's side of the message field lists (causal/dds/message_fields.hpp): fills a message from its history row,
// field by field, from the list causal-recorder wrote the row with. Columns the recorder only derives (a second
// UTC spelling of a time, an alarm event's data time) are not read back.
class RowFields {
 public:
  // Required: an empty integer cell makes the row unreadable (tables whose writer always fills them); else 0.
  enum class Integers { ZeroWhenEmpty, Required };
  RowFields(const char* table, const history::Row& row, Integers integers = Integers::ZeroWhenEmpty)
      : c_(table, row), required_(integers == Integers::Required) {}
  void text(const char* name, std::string& s) const { s = c_.text(name); }
  template <class T>
  void integer(const char* name, T& v) const {
    v = static_cast<T>(required_ ? c_.required_integer(name) : c_.integer(name));
  }
  void real(const char* name, double& v) const { v = c_.real(name); }
  // Empty reads as unknown (NaN) whether or not the message marks the hours to be read.
  void hours(const char* name, double& v, bool) const { v = c_.real(name); }
  void flag(const char* name, bool& b) const { b = c_.boolean(name); }
  void utc(const char* name, std::int64_t& ns) const { ns = c_.utc(name); }
  template <class E>
  void named(const char* name, E& e, bool present = true) const {
    if (present) e = enum_named<E>(c_.text(name));
  }
  void utc_copy(const char*, std::int64_t) const {}
  void derived(const char*, const std::string&) const {}

 private:
  HistoryCells c_;
  bool required_;
};

// make(row), or nullopt where the row does not convert.
template <typename T>
std::optional<T> guarded(T (*make)(const history::Row&), const history::Row& row) {
  try {
    return make(row);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The message a history row of its table (MessageFields<Message>::table) was written from, through its field list
// (causal/dds/message_fields.hpp); nullopt where the row does not convert.
template <typename Message>
std::optional<Message> message_from_row(const history::Row& row,
                                        RowFields::Integers integers = RowFields::Integers::ZeroWhenEmpty) {
  try {
    RowFields io(dds::MessageFields<Message>::table, row, integers);
    Message m;
    dds::MessageFields<Message>::list(io, m);
    return m;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The rows that convert, in the store's order; the others counted in `unreadable`.
template <typename T>
std::vector<T> readable(const std::vector<history::Row>& rows, std::optional<T> (*from_row)(const history::Row&),
                        std::uint64_t& unreadable) {
  std::vector<T> out;
  for (const history::Row& r : rows) {
    if (auto x = from_row(r)) {
      out.push_back(std::move(*x));
    } else {
      ++unreadable;
    }
  }
  return out;
}

}  // namespace causal::web
