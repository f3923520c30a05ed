#include "causal/io/csv_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "text_scan.hpp"

namespace causal::io {

namespace fs = std::filesystem;

std::string csv_quote(std::string_view cell) {
  bool needs = false;
  for (char c : cell) {
    if (c == ',' || c == '"' || c == '\n' || c == '\r') {
      needs = true;
      break;
    }
  }
  // Leading/trailing blanks are kept verbatim only inside quotes: many readers trim them otherwise, ours
  // (read_channel_csv, text_scan.hpp's trim) every one of is_blank_char's.
  if (!cell.empty() && (detail::is_blank_char(cell.front()) || detail::is_blank_char(cell.back()))) needs = true;
  if (!needs) return std::string(cell);
  std::string out;
  out.reserve(cell.size() + 2);
  out.push_back('"');
  for (char c : cell) {
    if (c == '"') out.push_back('"');
    out.push_back(c);
  }
  out.push_back('"');
  return out;
}

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buf[64];
  const auto result = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, result.ptr);
}

std::string format_integer(std::int64_t value) { return std::to_string(value); }
std::string format_integer(std::uint64_t value) { return std::to_string(value); }

std::string csv_line(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) line.push_back(',');
    line += csv_quote(cells[i]);
  }
  line.push_back('\n');
  return line;
}

void CsvWriter::write_row(const std::vector<std::string>& cells) {
  out_ << csv_line(cells);
  ++rows_;
}

namespace {

// First line of an existing file (without its line end), and whether the file ends with '\n'.
struct Existing {
  std::string first_line;
  bool ends_with_newline = true;
};

Existing inspect(const fs::path& path) {
  Existing e;
  std::ifstream in(path, std::ios::binary);
  std::getline(in, e.first_line);
  if (!e.first_line.empty() && e.first_line.back() == '\r') e.first_line.pop_back();
  in.clear();
  in.seekg(-1, std::ios::end);
  char last = '\n';
  if (in && in.get(last)) e.ends_with_newline = (last == '\n');
  return e;
}

}  // namespace

CsvFile::CsvFile(fs::path path, const std::vector<std::string>& header)
    : path_(std::move(path)), columns_(header.size()) {
  std::string header_line = csv_line(header);
  header_line.pop_back();
  std::error_code ec;
  const bool exists = fs::exists(path_, ec) && fs::file_size(path_, ec) > 0;
  bool need_newline = false;
  if (exists) {
    const Existing e = inspect(path_);
    if (e.first_line == header_line) {
      appended_ = true;
      need_newline = !e.ends_with_newline;  // the previous writer died mid-row: start a fresh line
    } else {
      for (int n = 1; n < 10000; ++n) {
        fs::path aside = path_;
        aside += ".old" + std::to_string(n);
        if (!fs::exists(aside, ec)) {
          fs::rename(path_, aside, ec);
          if (ec) throw std::runtime_error("cannot move '" + path_.string() + "' aside: " + ec.message());
          moved_aside_ = aside;
          break;
        }
      }
      if (moved_aside_.empty()) throw std::runtime_error("too many old copies of '" + path_.string() + "'");
    }
  }
  out_.open(path_, appended_ ? std::ios::binary | std::ios::app : std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot open '" + path_.string() + "' for writing");
  if (need_newline) out_ << '\n';
  if (!appended_) out_ << header_line << '\n';
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write to '" + path_.string() + "'");
}

void CsvFile::write_row(const std::vector<std::string>& cells) {
  out_ << csv_line(cells);
  if (!out_) throw std::runtime_error("cannot write to '" + path_.string() + "' (disk full?)");
  ++rows_;
}

void CsvFile::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write to '" + path_.string() + "' (disk full?)");
}

int CsvTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::optional<double> CsvTable::number(const std::string& cell) {
  if (cell.empty()) return std::nullopt;
  // strtod accepts "nan"/"inf" as written by format_number; a trailing remainder means "not a number".
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (end == cell.c_str() || *end != '\0') return std::nullopt;
  return v;
}

CsvTable parse_csv(std::string_view text, const std::string& path_for_messages) {
  CsvTable table;
  table.path = path_for_messages;
  std::vector<std::string> row;
  std::string cell;
  std::size_t line = 1, row_line = 1;
  bool in_quotes = false, after_quote = false, row_has_content = false;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(path_for_messages + ":" + std::to_string(row_line) + ": " + what);
  };
  auto end_row = [&]() {
    row.push_back(std::move(cell));
    cell.clear();
    if (table.header.empty()) {
      table.header = std::move(row);
    } else {
      if (row.size() > table.header.size()) {
        fail("row has " + std::to_string(row.size()) + " cells, header has " + std::to_string(table.header.size()));
      }
      row.resize(table.header.size());
      table.rows.push_back(std::move(row));
    }
    row.clear();
    row_has_content = false;
    after_quote = false;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          cell.push_back('"');
          ++i;
        } else {
          in_quotes = false;
          after_quote = true;
        }
      } else {
        if (c == '\n') ++line;
        cell.push_back(c);
      }
      continue;
    }
    if (c == ',') {
      row.push_back(std::move(cell));
      cell.clear();
      after_quote = false;
      row_has_content = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      if (row_has_content || !cell.empty() || after_quote) end_row();  // blank lines are skipped
      ++line;
      row_line = line;
    } else if (c == '"' && cell.empty() && !after_quote) {
      in_quotes = true;
      row_has_content = true;
    } else {
      if (after_quote) fail("text after a closing quote");
      cell.push_back(c);
      row_has_content = true;
    }
  }
  if (in_quotes) fail("unterminated quoted cell");
  if (row_has_content || !cell.empty()) end_row();
  return table;
}

CsvTable read_csv(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + path.string() + "'");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_csv(buffer.str(), path.string());
}

}  // namespace causal::io
