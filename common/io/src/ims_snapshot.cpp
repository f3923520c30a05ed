// IMS snapshot reader: whitespace-separated numbers, no header, plain or gzip.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "causal/io/ims_directory.hpp"
#include "causal/io/input_error.hpp"
#include "text_file.hpp"
#include "text_scan.hpp"

namespace causal::io {

Eigen::MatrixXd read_ims_snapshot(const std::string& path, int expected_channels) {
  if (expected_channels < 0) throw InputError(path, 0, "expected_channels must be >= 0");
  const std::string text = detail::read_text_file(path);
  if (detail::is_blank_line(text)) throw InputError(path, 0, "empty file: no data rows");

  std::size_t g = static_cast<std::size_t>(expected_channels);
  std::vector<double> data;  // row-major
  // ~6.5 bytes per value in the IMS files ("-0.049\t"); over-reserve a little to avoid regrowth.
  data.reserve(text.size() / 5 + 16);
  std::size_t rows = 0;

  detail::LineCursor cursor(text);
  std::string_view line;
  while (cursor.next(line)) {
    std::size_t col = 0;
    std::size_t i = 0;
    const std::size_t n = line.size();
    bool any = false;
    while (true) {
      while (i < n && detail::is_blank_char(line[i])) ++i;
      if (i >= n) break;
      std::size_t j = i;
      while (j < n && !detail::is_blank_char(line[j])) ++j;
      const std::string_view tok = line.substr(i, j - i);
      i = j;
      any = true;
      const std::optional<double> v = detail::parse_double(tok);
      if (!v) {
        throw InputError(path, cursor.line_number(),
                         "not a number: " + detail::quote_token(tok) + " (column " + std::to_string(col + 1) + ")");
      }
      if (!std::isfinite(*v)) {
        throw InputError(path, cursor.line_number(),
                         "non-finite value " + detail::quote_token(tok) + " (column " + std::to_string(col + 1) +
                             ")");
      }
      if (g != 0 && col >= g) {
        throw InputError(path, cursor.line_number(),
                         "ragged row: more than " + std::to_string(g) + " values (expected " + std::to_string(g) +
                             ")");
      }
      data.push_back(*v);
      ++col;
    }
    if (!any) continue;  // blank line
    if (g == 0) g = col;  // first row defines the width
    if (col != g) {
      throw InputError(path, cursor.line_number(),
                       "ragged row: " + std::to_string(col) + " values, expected " + std::to_string(g));
    }
    ++rows;
  }
  if (rows == 0) throw InputError(path, 0, "empty file: no data rows");

  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(data.data(), static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(g));
}

}  // namespace causal::io
