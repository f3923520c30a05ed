// causal-recorder's side of the message field lists (causal/dds/message_fields.hpp): a message's row as its CSV
// file and historian table spell it (numbers in the shortest round-trip form, times as UTC text, enums by name),
// and the header from the same list, so header and row cannot disagree.
#pragma once

#include "causal/dds/message_fields.hpp"
#include "causal_twin.h"

#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace causal::recorder {

// The writer: one cell per column, in the list's order, and the columns' names.
class RowCells {
 public:
  void text(const char* name, const std::string& s) { push(name, s); }
  template <class T>
  void integer(const char* name, T v) {
    static_assert(std::is_integral_v<T>, "integer columns hold integer fields");
    if constexpr (std::is_signed_v<T>) {
      push_integer(name, static_cast<std::int64_t>(v));
    } else {
      push_integer(name, static_cast<std::uint64_t>(v));
    }
  }
  void real(const char* name, double v);
  void hours(const char* name, double v, bool known);
  void flag(const char* name, bool b) { push(name, b ? "true" : "false"); }
  void utc(const char* name, std::int64_t ns);
  void utc_copy(const char* name, std::int64_t ns) { utc(name, ns); }
  void named(const char* name, causal_twin::Severity e, bool present = true);
  void named(const char* name, causal_twin::AlarmState e, bool present = true);
  void named(const char* name, causal_twin::AlarmActionKind e, bool present = true);
  void derived(const char* name, const std::string& cell) { push(name, cell); }
  std::vector<std::string> take_cells() { return std::move(cells_); }
  std::vector<std::string> take_names() { return std::move(names_); }

 private:
  void push(const char* name, std::string cell) {
    names_.emplace_back(name);
    cells_.push_back(std::move(cell));
  }
  void push_integer(const char* name, std::int64_t v);
  void push_integer(const char* name, std::uint64_t v);
  std::vector<std::string> names_, cells_;
};

// The columns of Message's CSV file (= its historian table's), made once.
template <class Message>
const std::vector<std::string>& header_of() {
  static const std::vector<std::string> names = [] {
    const Message any{};
    RowCells io;
    dds::MessageFields<Message>::list(io, any);
    return io.take_names();
  }();
  return names;
}

// A message's row (the alarm's: alarm_row, record_rows.hpp, which knows its event time).
template <class Message>
std::vector<std::string> row_of(const Message& message) {
  RowCells io;
  dds::MessageFields<Message>::list(io, message);
  return io.take_cells();
}

}  // namespace causal::recorder
