#include "causal/history/json_cells.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace causal::history {

std::string json_string_array(const std::vector<std::string>& items) {
  std::string s = "[";
  for (std::size_t i = 0; i < items.size(); ++i) {
    s += i ? ",\"" : "\"";
    for (const unsigned char c : items[i]) {
      if (c == '"' || c == '\\') {
        s += '\\';
        s += static_cast<char>(c);
      } else if (c < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", c);
        s += buf;
      } else {
        s += static_cast<char>(c);
      }
    }
    s += '"';
  }
  return s + "]";
}

std::string json_number_array(const std::vector<std::string>& cells) {
  std::string s = "[";
  for (std::size_t i = 0; i < cells.size(); ++i) {
    s += i ? "," : "";
    char* end = nullptr;
    const double v = cells[i].empty() ? NAN : std::strtod(cells[i].c_str(), &end);
    const bool number = !cells[i].empty() && end != nullptr && *end == '\0' && std::isfinite(v);
    s += number ? cells[i] : "null";
  }
  return s + "]";
}

namespace {
void skip_blanks(const std::string& t, std::size_t& i) {
  while (i < t.size() && (t[i] == ' ' || t[i] == '\n' || t[i] == '\t' || t[i] == '\r')) ++i;
}
}  // namespace

std::optional<std::vector<std::string>> parse_json_string_array(const std::string& t) {
  std::vector<std::string> out;
  std::size_t i = 0;
  skip_blanks(t, i);
  if (i >= t.size() || t[i++] != '[') return std::nullopt;
  skip_blanks(t, i);
  if (i < t.size() && t[i] == ']') return out;
  while (i < t.size()) {
    skip_blanks(t, i);
    if (t[i++] != '"') return std::nullopt;
    std::string item;
    while (i < t.size() && t[i] != '"') {
      if (t[i] == '\\' && i + 1 < t.size()) {
        ++i;
        if (t[i] == 'u' && i + 4 < t.size()) {
          item += static_cast<char>(std::strtol(t.substr(i + 1, 4).c_str(), nullptr, 16));
          i += 4;
        } else {
          item += t[i];
        }
      } else {
        item += t[i];
      }
      ++i;
    }
    if (i >= t.size()) return std::nullopt;
    ++i;  // closing quote
    out.push_back(std::move(item));
    skip_blanks(t, i);
    if (i < t.size() && t[i] == ',') {
      ++i;
      continue;
    }
    if (i < t.size() && t[i] == ']') return out;
    return std::nullopt;
  }
  return std::nullopt;
}

std::optional<std::vector<std::optional<double>>> parse_json_number_array(const std::string& t) {
  std::vector<std::optional<double>> out;
  std::size_t i = 0;
  skip_blanks(t, i);
  if (i >= t.size() || t[i++] != '[') return std::nullopt;
  skip_blanks(t, i);
  if (i < t.size() && t[i] == ']') return out;
  while (i < t.size()) {
    skip_blanks(t, i);
    if (t.compare(i, 4, "null") == 0) {
      out.emplace_back();
      i += 4;
    } else {
      const char* start = t.c_str() + i;
      char* end = nullptr;
      const double v = std::strtod(start, &end);
      if (end == start) return std::nullopt;
      out.emplace_back(v);
      i += static_cast<std::size_t>(end - start);
    }
    skip_blanks(t, i);
    if (i < t.size() && t[i] == ',') {
      ++i;
      continue;
    }
    if (i < t.size() && t[i] == ']') return out;
    return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace causal::history
