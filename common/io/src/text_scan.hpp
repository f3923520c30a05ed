// Internal: line iteration, locale-free number parsing and CSV field splitting shared by the readers.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace causal::io::detail {

// Iterates the lines of a text buffer; strips a trailing '\r' (CRLF files) and a leading UTF-8 BOM.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
  }
  // Next line (without terminator); false at end. line_number() is then 1-based.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    ++line_;
    return true;
  }
  std::size_t line_number() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

inline bool is_blank_char(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank_char(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank_char(s.back())) s.remove_suffix(1);
  return s;
}

inline bool is_blank_line(std::string_view s) { return trim(s).empty(); }

// Clinger's fast path for the common short decimal "[-]ddd.ddd" (<= 15 significant digits, no exponent):
// the digits form an integer m < 2^53 and 10^k (k <= 15) is exact, so m / 10^k is ONE correctly rounded
// IEEE division: bit-identical to from_chars, ~3x faster on IMS files. Returns false to fall back.
[[nodiscard]] inline bool parse_short_decimal(std::string_view tok, double& out) {
  static constexpr double kPow10[16] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  std::size_t i = 0;
  const bool neg = !tok.empty() && tok[0] == '-';
  if (neg) ++i;
  std::uint64_t m = 0;
  int digits = 0, frac = 0;
  bool dot = false;
  for (; i < tok.size(); ++i) {
    const char c = tok[i];
    if (c >= '0' && c <= '9') {
      if (++digits > 15) return false;
      m = m * 10 + static_cast<std::uint64_t>(c - '0');
      frac += dot ? 1 : 0;
    } else if (c == '.' && !dot) {
      dot = true;
    } else {
      return false;  // exponent, second dot, text: let from_chars decide
    }
  }
  if (digits == 0) return false;
  const double v = static_cast<double>(m) / kPow10[frac];
  out = neg ? -v : v;
  return true;
}

// Whole token must be a number. Accepts a leading '+' (from_chars does not). "nan"/"inf" parse
// (callers decide whether non-finite values are allowed).
[[nodiscard]] inline std::optional<double> parse_double(std::string_view tok) {
  if (tok.empty()) return std::nullopt;
  if (double fast = 0.0; parse_short_decimal(tok, fast)) return fast;
  if (tok.front() == '+') {
    tok.remove_prefix(1);
    if (tok.empty() || tok.front() == '-' || tok.front() == '+') return std::nullopt;
  }
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  // result_out_of_range: denormal underflow/overflow; treat as not a usable number.
  if (ec != std::errc() || ptr != tok.data() + tok.size()) return std::nullopt;
  return v;
}

[[nodiscard]] inline std::optional<std::int64_t> parse_int64(std::string_view tok) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  if (ec != std::errc() || ptr != tok.data() + tok.size() || tok.empty()) return std::nullopt;
  return v;
}

// Splits one CSV line on ',' into trimmed fields. Double-quoted fields are unquoted ("" -> ") into
// `scratch`, which the returned views may point into (valid until the next call). Returns false for an
// unterminated quote or text after a closing quote.
bool split_csv_line(std::string_view line, std::vector<std::string_view>& fields, std::string& scratch);

// Reads the header row of a CSV file (its first non-blank line) into `fields` and returns its line number.
// Throws InputError(path, ...) for an empty file or malformed quoting.
// Reads the next non-blank data row into `fields` and returns its line number, 0 at the end of the file.
// Throws InputError(path, line, ...) for malformed quoting or a row that does not have `width` fields.
std::size_t next_csv_row(const std::string& path, LineCursor& cursor, std::size_t width,
                         std::vector<std::string_view>& fields, std::string& scratch);

std::size_t read_csv_header(const std::string& path, LineCursor& cursor, std::vector<std::string_view>& fields,
                            std::string& scratch);

// One CSV file being read row by row: its text, a cursor over it and the current row's fields (views into the
// text or into scratch). The constructor reads the header row into `fields` (read_csv_header's errors).
struct CsvScan {
  explicit CsvScan(const std::string& file);
  CsvScan(const CsvScan&) = delete;  // the cursor and the fields point into `text`
  CsvScan& operator=(const CsvScan&) = delete;
  // The next data row into `fields`: its line number, 0 at the end (next_csv_row's errors).
  std::size_t next_row(std::size_t width) { return next_csv_row(path, cursor, width, fields, scratch); }

  std::string path;
  std::string text;
  LineCursor cursor;
  std::vector<std::string_view> fields;
  std::string scratch;
  std::size_t header_line = 0;
};

// Short printable excerpt of a bad token for error messages.
std::string quote_token(std::string_view tok);

// ASCII lower-case copy.
std::string to_lower(std::string_view s);

}  // namespace causal::io::detail
