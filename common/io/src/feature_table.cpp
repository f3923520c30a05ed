// Per-snapshot feature table reader (merged_dataset and derived_per_file_stats layouts).
#include "causal/io/feature_table.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "causal/io/input_error.hpp"
#include "causal/io/time_format.hpp"
#include "text_file.hpp"
#include "text_scan.hpp"

namespace causal::io {
namespace {

bool is_time_name(const std::string& lower) {
  return lower == "timestamp" || lower == "time" || lower == "time_utc";
}

// causal-recorder's conditions_<group>_<feature>.csv: snapshot,time_ns,time_utc,<channels>.
bool is_bookkeeping_name(const std::string& lower) {
  return is_time_name(lower) || lower == "file" || lower == "index" || lower == "n" || lower == "snapshot" ||
         lower == "time_ns";
}

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

bool is_condition_feature_name(const std::string& s) {
  static const std::set<std::string> known = {"meanabs", "rms", "kurtosis", "peak", "peakabs", "min",
                                              "max",     "mean", "std",     "skewness", "crest"};
  return known.count(s) > 0;
}

}  // namespace

std::string per_feature_suffix(const FeatureTable& all_columns, const std::string& feature) {
  std::set<std::string> features;
  for (const std::string& name : all_columns.channel_names) {
    const auto cut = name.rfind('_');
    if (cut == std::string::npos || cut == 0) return "";
    const std::string f = detail::to_lower(name.substr(cut + 1));
    if (!is_condition_feature_name(f)) return "";  // a channel name that happens to contain '_'
    features.insert(f);
  }
  if (features.size() < 2) return "";
  if (features.count(feature) == 0) {
    std::string list;
    for (const auto& f : features) list += (list.empty() ? "" : ", ") + f;
    throw std::invalid_argument("the table has several features per channel (" + list + "), not '" + feature + "'");
  }
  return "_" + feature;
}

FeatureTable read_feature_table(const std::string& path, const std::string& column_suffix) {
  detail::CsvScan csv(path);
  const std::vector<std::string_view>& fields = csv.fields;
  const std::size_t header_line = csv.header_line;
  const std::vector<std::string> header(fields.begin(), fields.end());
  const std::size_t width = header.size();

  // Time column: time_ns (integer ns, exact: the recorder's files), else a column named timestamp/time/time_utc,
  // else the first column.
  std::size_t time_col = 0;
  bool time_in_ns = false;
  for (std::size_t c = 0; c < width; ++c) {
    if (detail::to_lower(header[c]) == "time_ns") {
      time_col = c;
      time_in_ns = true;
      break;
    }
  }
  for (std::size_t c = 0; c < width && !time_in_ns; ++c) {
    if (is_time_name(detail::to_lower(header[c]))) {
      time_col = c;
      break;
    }
  }

  // A causal-recorder conditions file (snapshot,time_ns,...) holds one feature, named in its file name: every
  // other column is a channel whatever the suffix asked for.
  const bool recorder_layout = time_in_ns && width > 0 && detail::to_lower(header[0]) == "snapshot";
  const bool every_column = column_suffix.empty() || recorder_layout;
  FeatureTable table;
  std::vector<std::size_t> cols;  // file columns of the channels
  for (std::size_t c = 0; c < width; ++c) {
    if (c == time_col) continue;
    if (every_column) {
      if (is_bookkeeping_name(detail::to_lower(header[c]))) continue;
      if (header[c].empty()) throw InputError(path, header_line, "empty column name in column " + std::to_string(c + 1));
      cols.push_back(c);
      table.channel_names.push_back(header[c]);
    } else if (header[c].size() > column_suffix.size() && ends_with(header[c], column_suffix)) {
      cols.push_back(c);
      table.channel_names.push_back(header[c].substr(0, header[c].size() - column_suffix.size()));
    }
  }
  if (cols.empty()) {
    std::string names;
    for (const std::string& h : header) names += (names.empty() ? "'" : ", '") + h + "'";
    throw InputError(path, header_line,
                     (column_suffix.empty() ? std::string("no channel column")
                                            : "no column name ends with '" + column_suffix + "'") +
                         "; columns are: " + names);
  }

  const std::size_t g = cols.size();
  std::vector<double> data;  // row-major
  std::size_t rows = 0;
  std::size_t ln = 0;
  while ((ln = csv.next_row(width)) != 0) {
    const std::optional<std::int64_t> t =
        time_in_ns ? detail::parse_int64(fields[time_col]) : parse_utc(fields[time_col]);
    if (!t) {
      throw InputError(path, ln,
                       "bad time stamp " + detail::quote_token(fields[time_col]) +
                           " (want YYYY-MM-DD hh:mm:ss or YYYY.MM.DD.hh.mm.ss)");
    }
    if (!table.time_ns.empty() && *t <= table.time_ns.back()) {
      throw InputError(path, ln,
                       "time stamps not strictly increasing: " + format_utc(*t) + " after " +
                           format_utc(table.time_ns.back()));
    }
    table.time_ns.push_back(*t);
    for (std::size_t k = 0; k < g; ++k) {
      const std::string_view cell = fields[cols[k]];
      const std::optional<double> v = detail::parse_double(cell);
      if (!v) {
        throw InputError(path, ln,
                         "not a number: " + detail::quote_token(cell) + " (column '" + header[cols[k]] + "')");
      }
      if (!std::isfinite(*v)) {
        throw InputError(path, ln,
                         "non-finite value " + detail::quote_token(cell) + " (column '" + header[cols[k]] + "')");
      }
      data.push_back(*v);
    }
    ++rows;
  }
  if (rows == 0) throw InputError(path, 0, "no data rows");
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  table.values = Eigen::Map<const RowMajor>(data.data(), static_cast<Eigen::Index>(rows),
                                            static_cast<Eigen::Index>(g));
  return table;
}

}  // namespace causal::io
