#include "text_scan.hpp"
#include "text_file.hpp"

#include "causal/io/input_error.hpp"

namespace causal::io::detail {

bool split_csv_line(std::string_view line, std::vector<std::string_view>& fields, std::string& scratch) {
  fields.clear();
  if (line.find('"') == std::string_view::npos) {
    // Fast path (all numeric rows): views straight into the line.
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      if (comma == std::string_view::npos) {
        fields.push_back(trim(line.substr(start)));
        return true;
      }
      fields.push_back(trim(line.substr(start, comma - start)));
      start = comma + 1;
    }
  }
  // Quoted path. Reserve so that views into scratch stay valid while we append.
  scratch.clear();
  scratch.reserve(line.size());
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && is_blank_char(line[i])) ++i;
    if (i < line.size() && line[i] == '"') {
      ++i;
      const std::size_t begin = scratch.size();
      bool closed = false;
      while (i < line.size()) {
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            scratch.push_back('"');
            i += 2;
            continue;
          }
          ++i;
          closed = true;
          break;
        }
        scratch.push_back(line[i++]);
      }
      if (!closed) return false;
      fields.emplace_back(scratch.data() + begin, scratch.size() - begin);
      while (i < line.size() && is_blank_char(line[i])) ++i;
      if (i == line.size()) return true;
      if (line[i] != ',') return false;
      ++i;
    } else {
      const std::size_t comma = line.find(',', i);
      const std::size_t stop = comma == std::string_view::npos ? line.size() : comma;
      const std::string_view field = trim(line.substr(i, stop - i));
      if (field.find('"') != std::string_view::npos) return false;
      fields.push_back(field);
      if (comma == std::string_view::npos) return true;
      i = comma + 1;
    }
  }
}

std::string quote_token(std::string_view tok) {
  constexpr std::size_t kMax = 40;
  std::string s = "'";
  for (std::size_t i = 0; i < tok.size() && i < kMax; ++i) {
    const char c = tok[i];
    s += (static_cast<unsigned char>(c) < 0x20) ? '?' : c;
  }
  if (tok.size() > kMax) s += "...";
  s += "'";
  return s;
}

std::string to_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

CsvScan::CsvScan(const std::string& file) : path(file), text(read_text_file(file)), cursor(text) {
  header_line = read_csv_header(path, cursor, fields, scratch);
}

std::size_t read_csv_header(const std::string& path, LineCursor& cursor, std::vector<std::string_view>& fields,
                            std::string& scratch) {
  std::string_view line;
  while (cursor.next(line)) {
    if (is_blank_line(line)) continue;
    const std::size_t header_line = cursor.line_number();
    if (!split_csv_line(line, fields, scratch)) throw InputError(path, header_line, "malformed quoting");
    return header_line;
  }
  throw InputError(path, 0, "empty file: no header row");
}

std::size_t next_csv_row(const std::string& path, LineCursor& cursor, std::size_t width,
                         std::vector<std::string_view>& fields, std::string& scratch) {
  std::string_view line;
  while (cursor.next(line)) {
    if (is_blank_line(line)) continue;
    const std::size_t ln = cursor.line_number();
    if (!split_csv_line(line, fields, scratch)) throw InputError(path, ln, "malformed quoting");
    if (fields.size() != width) {
      throw InputError(path, ln,
                       "ragged row: " + std::to_string(fields.size()) + " fields, header has " + std::to_string(width));
    }
    return ln;
  }
  return 0;
}

}  // namespace causal::io::detail
