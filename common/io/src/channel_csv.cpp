// Channel CSV reader/writer (see channel_csv.hpp for the dialect).
#include "causal/io/channel_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

#include "causal/io/csv_format.hpp"
#include "causal/io/input_error.hpp"
#include "causal/io/time_format.hpp"
#include "text_file.hpp"
#include "text_scan.hpp"

namespace causal::io {
namespace {

enum class FirstColumn { Channel, Index, Time, TimeNs };

// Bookkeeping columns before the channels. causal-recorder's conditions_<group>_<feature>.csv starts with
// snapshot,time_ns,time_utc: all three are bookkeeping, so its files read as channel tables.
FirstColumn classify_first_column(std::string_view name) {
  const std::string n = detail::to_lower(name);
  if (n == "n" || n == "index" || n == "snapshot") return FirstColumn::Index;
  if (n == "time" || n == "timestamp" || n == "time_utc") return FirstColumn::Time;
  if (n == "time_ns") return FirstColumn::TimeNs;
  return FirstColumn::Channel;
}

// A time cell: a time stamp (parse_utc) or a plain number of seconds.
std::optional<std::int64_t> parse_time_cell(std::string_view cell) {
  if (auto t = parse_utc(cell)) return t;
  const std::optional<double> secs = detail::parse_double(cell);
  // 9.2e9 s is the int64 ns range; beyond it the conversion would overflow.
  if (!secs || !std::isfinite(*secs) || std::abs(*secs) > 9.2e9) return std::nullopt;
  return static_cast<std::int64_t>(std::llround(*secs * 1e9));
}

void append_double(std::string& out, double v) {
  // Shortest representation that round-trips exactly (C++17 <charconv>); "nan"/"inf"/"-inf" for
  // non-finite values, which from_chars reads back.
  std::array<char, 32> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.append(buf.data(), res.ptr);
}

}  // namespace

ChannelTable read_channel_csv(const std::string& path) {
  detail::CsvScan csv(path);
  const std::vector<std::string_view>& fields = csv.fields;
  const std::size_t header_line = csv.header_line;

  // Leading bookkeeping columns (see classify_first_column); the time comes from time_ns when there is one
  // (exact), else from the first time column.
  std::vector<FirstColumn> leading;
  while (leading.size() < fields.size() && classify_first_column(fields[leading.size()]) != FirstColumn::Channel) {
    leading.push_back(classify_first_column(fields[leading.size()]));
  }
  const std::size_t skip = leading.size();
  std::size_t time_col = skip;  // skip = no time column
  FirstColumn time_kind = FirstColumn::Index;
  for (std::size_t c = 0; c < skip; ++c) {
    if (leading[c] == FirstColumn::TimeNs || (leading[c] == FirstColumn::Time && time_col == skip)) {
      time_col = c;
      time_kind = leading[c];
    }
  }
  const FirstColumn first = skip == 0 ? FirstColumn::Channel : time_kind;
  ChannelTable table;
  std::set<std::string> seen;
  bool all_numeric = true;
  for (std::size_t c = skip; c < fields.size(); ++c) {
    const std::string name(fields[c]);
    if (name.empty()) {
      throw InputError(path, header_line, "empty channel name in column " + std::to_string(c + 1));
    }
    if (!seen.insert(name).second) throw InputError(path, header_line, "duplicate channel name '" + name + "'");
    if (!detail::parse_double(name)) all_numeric = false;
    table.channel_names.push_back(name);
  }
  if (table.channel_names.empty()) throw InputError(path, header_line, "no channel column in header");
  if (all_numeric && first == FirstColumn::Channel) {
    throw InputError(path, header_line, "header row is numeric: the file needs a header row of channel names");
  }

  const std::size_t g = table.channel_names.size();
  const std::size_t width = g + skip;
  std::vector<double> data;  // row-major
  std::size_t rows = 0;
  std::size_t ln = 0;
  while ((ln = csv.next_row(width)) != 0) {
    if (first == FirstColumn::Time) {
      const std::optional<std::int64_t> t = parse_time_cell(fields[time_col]);
      if (!t) throw InputError(path, ln, "bad time " + detail::quote_token(fields[time_col]));
      table.time_ns.push_back(*t);
    } else if (first == FirstColumn::TimeNs) {
      const std::optional<std::int64_t> t = detail::parse_int64(fields[time_col]);
      if (!t) throw InputError(path, ln, "bad integer time_ns " + detail::quote_token(fields[time_col]));
      table.time_ns.push_back(*t);
    }
    for (std::size_t c = skip; c < width; ++c) {
      const std::optional<double> v = detail::parse_double(fields[c]);
      if (!v) {
        throw InputError(path, ln,
                         "not a number: " + detail::quote_token(fields[c]) + " (column '" +
                             table.channel_names[c - skip] + "')");
      }
      data.push_back(*v);
    }
    ++rows;
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  table.values = Eigen::Map<const RowMajor>(data.data(), static_cast<Eigen::Index>(rows),
                                            static_cast<Eigen::Index>(g));
  return table;
}

void write_channel_csv(const std::string& path, const ChannelTable& table) {
  const std::size_t g = table.channel_names.size();
  if (g == 0) throw std::invalid_argument("write_channel_csv: no channel names");
  if (static_cast<std::size_t>(table.values.cols()) != g) {
    throw std::invalid_argument("write_channel_csv: " + std::to_string(g) + " names but values has " +
                                std::to_string(table.values.cols()) + " columns");
  }
  const auto n = static_cast<std::size_t>(table.values.rows());
  if (!table.time_ns.empty() && table.time_ns.size() != n) {
    throw std::invalid_argument("write_channel_csv: time_ns has " + std::to_string(table.time_ns.size()) +
                                " entries but values has " + std::to_string(n) + " rows");
  }
  std::set<std::string> seen;
  bool all_numeric = true;
  for (std::size_t c = 0; c < g; ++c) {
    const std::string& name = table.channel_names[c];
    if (name.empty()) throw std::invalid_argument("write_channel_csv: empty channel name");
    if (!seen.insert(name).second) throw std::invalid_argument("write_channel_csv: duplicate name '" + name + "'");
    // The reader would take these as the index/time column.
    if (c == 0 && table.time_ns.empty() && classify_first_column(name) != FirstColumn::Channel) {
      throw std::invalid_argument("write_channel_csv: first channel may not be named '" + name +
                                  "' (reserved for the time/index column)");
    }
    if (!detail::parse_double(name)) all_numeric = false;
  }
  if (all_numeric && table.time_ns.empty()) {
    throw std::invalid_argument("write_channel_csv: all-numeric names would be read back as a missing header");
  }

  std::string out;
  out.reserve(64 + n * g * 12);
  if (!table.time_ns.empty()) out += "timestamp,";
  for (std::size_t c = 0; c < g; ++c) {
    if (c) out += ',';
    out += csv_quote(table.channel_names[c]);
  }
  out += '\n';
  for (std::size_t r = 0; r < n; ++r) {
    if (!table.time_ns.empty()) {
      out += format_utc_exact(table.time_ns[r]);
      out += ',';
    }
    for (std::size_t c = 0; c < g; ++c) {
      if (c) out += ',';
      append_double(out, table.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)));
    }
    out += '\n';
  }
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw InputError(path, 0, "cannot open for writing");
  f.write(out.data(), static_cast<std::streamsize>(out.size()));
  f.close();
  if (!f) throw InputError(path, 0, "write failed");
}

}  // namespace causal::io
