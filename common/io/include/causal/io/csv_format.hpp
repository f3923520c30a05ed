// The CSV dialect shared by causal-recorder (writer) and causal-report (reader): RFC 4180, comma
// separated, "\n" line ends, a header row, text cells quoted only when they must be, numbers in the
// shortest form that reads back to the same double. Std only.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace causal::io {

// Quotes a cell when it contains a comma, a double quote, CR/LF or leading/trailing blanks (space, tab, CR,
// VT, FF: what the readers trim) (RFC 4180 section 2.6-2.7: quotes inside are doubled). Other cells, the
// empty one too, are returned unchanged. The one CSV quoter: the recorder's rows and channel CSV headers.
std::string csv_quote(std::string_view cell);

// Shortest round-trip decimal form ("0.1", "1e-05", "nan", "inf", "-inf").
std::string format_number(double value);
std::string format_integer(std::int64_t value);
std::string format_integer(std::uint64_t value);

// One CSV line (with its "\n") of already formatted cells; each is quoted as needed.
std::string csv_line(const std::vector<std::string>& cells);

// Writes rows to a stream: header first (if not empty), then one line per row.
class CsvWriter {
 public:
  explicit CsvWriter(std::ostream& out) : out_(out) {}
  void write_row(const std::vector<std::string>& cells);
  std::uint64_t rows() const { return rows_; }

 private:
  std::ostream& out_;
  std::uint64_t rows_ = 0;
};

// A CSV file under a fixed header, written row by row. An existing file with exactly this header is
// appended to (a restarted recorder continues its history); an existing file with another header is
// renamed to <name>.old<N> first, so nothing recorded earlier is overwritten.
// Throws std::runtime_error naming the file when it cannot be opened or written.
class CsvFile {
 public:
  CsvFile(std::filesystem::path path, const std::vector<std::string>& header);
  void write_row(const std::vector<std::string>& cells);
  void flush();
  std::uint64_t rows_written() const { return rows_; }  // this session, header excluded
  std::size_t columns() const { return columns_; }
  const std::filesystem::path& path() const { return path_; }
  bool appended() const { return appended_; }
  const std::filesystem::path& moved_aside() const { return moved_aside_; }  // empty unless renamed

 private:
  std::filesystem::path path_;
  std::filesystem::path moved_aside_;
  std::ofstream out_;
  std::size_t columns_ = 0;
  std::uint64_t rows_ = 0;
  bool appended_ = false;
};

// Parsed CSV file: header + rows of raw (unquoted) cells. Rows shorter than the header are padded with
// empty cells; longer rows are an error.
struct CsvTable {
  std::string path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  // Column index of `name`, or -1.
  int column(std::string_view name) const;
  // Cell as a double: nullopt when empty or not a number.
  static std::optional<double> number(const std::string& cell);
};

// Parses RFC 4180 text (quoted cells may hold commas, doubled quotes and line breaks; CRLF accepted).
// Throws std::runtime_error "<path>:<line>: ..." for an unterminated quote, text after a closing quote,
// or a row with more cells than the header. Empty text gives an empty table (no header).
[[nodiscard]] CsvTable parse_csv(std::string_view text, const std::string& path_for_messages = "<text>");
CsvTable read_csv(const std::filesystem::path& path);

}  // namespace causal::io
