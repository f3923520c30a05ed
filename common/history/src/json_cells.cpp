#include "causal/history/json_cells.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

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

// A JSON array of one kind of item: `item(t, i, out)` reads the item at t[i] into out (moving i past it) and
// says whether it was one; anything else than items between '[', ',' and ']' (blanks aside) is nullopt.
template <typename T, typename Item>
std::optional<std::vector<T>> parse_json_array(const std::string& t, Item item) {
  std::vector<T> out;
  std::size_t i = 0;
  skip_blanks(t, i);
  if (i >= t.size() || t[i++] != '[') return std::nullopt;
  skip_blanks(t, i);
  if (i < t.size() && t[i] == ']') return out;
  while (i < t.size()) {
    skip_blanks(t, i);
    if (!item(t, i, out)) return std::nullopt;
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

// One string item; a \uXXXX escape is read as one byte (json_string_array writes it only for control characters).
bool read_string_item(const std::string& t, std::size_t& i, std::vector<std::string>& out) {
  if (t[i++] != '"') return false;
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
  if (i >= t.size()) return false;
  ++i;  // closing quote
  out.push_back(std::move(item));
  return true;
}

// One number or null (NaN and infinities are written as null).
bool read_number_item(const std::string& t, std::size_t& i, std::vector<std::optional<double>>& out) {
  if (t.compare(i, 4, "null") == 0) {
    out.emplace_back();
    i += 4;
    return true;
  }
  const char* start = t.c_str() + i;
  char* end = nullptr;
  const double v = std::strtod(start, &end);
  if (end == start) return false;
  out.emplace_back(v);
  i += static_cast<std::size_t>(end - start);
  return true;
}

}  // namespace

std::optional<std::vector<std::string>> parse_json_string_array(const std::string& t) {
  return parse_json_array<std::string>(t, read_string_item);
}

std::optional<std::vector<std::optional<double>>> parse_json_number_array(const std::string& t) {
  return parse_json_array<std::optional<double>>(t, read_number_item);
}

}  // namespace causal::history
