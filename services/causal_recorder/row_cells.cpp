#include "row_cells.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/io/csv_format.hpp"
#include "causal/io/time_format.hpp"

#include <cmath>

namespace causal::recorder {

void RowCells::real(const char* name, double v) { push(name, io::format_number(v)); }

// Hours: empty when unknown (NaN), as the interface says, and when the message says they are not to be read.
void RowCells::hours(const char* name, double v, bool known) {
  push(name, known && std::isfinite(v) ? io::format_number(v) : std::string());
}

// 0 is "not set": an empty cell.
void RowCells::utc(const char* name, std::int64_t ns) { push(name, ns == 0 ? std::string() : io::format_utc(ns)); }

void RowCells::named(const char* name, causal_twin::Severity e, bool present) {
  push(name, present ? dds::to_string(e, "?") : "");
}

void RowCells::named(const char* name, causal_twin::AlarmState e, bool present) {
  push(name, present ? dds::to_string(e, "?") : "");
}

void RowCells::named(const char* name, causal_twin::AlarmActionKind e, bool present) {
  push(name, present ? dds::to_string(e, "unknown") : "");
}

void RowCells::push_integer(const char* name, std::int64_t v) { push(name, io::format_integer(v)); }
void RowCells::push_integer(const char* name, std::uint64_t v) { push(name, io::format_integer(v)); }

}  // namespace causal::recorder
