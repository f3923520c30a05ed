#include "ingest_block.hpp"

#include "ingest_block_checks.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace causal::ingest {

const char* reason_name(RejectReason reason) {
  switch (reason) {
    case RejectReason::Malformed:
      return "malformed";
    case RejectReason::Truncated:
      return "truncated";
    case RejectReason::Shape:
      return "shape";
    case RejectReason::Field:
      return "field";
    case RejectReason::Oversize:
      return "oversize";
    case RejectReason::LayoutChange:
      return "layout_change";
    case RejectReason::Duplicate:
      return "duplicate";
    case RejectReason::OutOfOrder:
      return "out_of_order";
  }
  return "unknown";
}

namespace {

constexpr const char kBinaryMagic[] = "CTB1";
constexpr std::size_t kBinaryFixedHeader = 36;
constexpr const char kCsvMagic[] = "#block";

}  // namespace

namespace detail {

ParseResult reject(RejectReason reason, std::string detail) {
  ParseResult r;
  r.reason = reason;
  r.detail = std::move(detail);
  return r;
}

ParseResult accept(IngestBlock block) {
  for (const double v : block.samples) {
    if (!std::isfinite(v)) ++block.non_finite;
  }
  ParseResult r;
  r.block = std::move(block);
  return r;
}

// Checks common to every encoding once the header is known. nullopt when fine, else the rejection.
std::optional<ParseResult> check_header(const IngestBlock& b, const BlockLimits& limits) {
  if (b.asset_group.empty()) return reject(RejectReason::Field, "empty asset_group");
  if (b.asset_group.size() > limits.max_name_bytes) return reject(RejectReason::Field, "asset_group too long");
  if (b.unit.size() > limits.max_name_bytes) return reject(RejectReason::Field, "unit too long");
  if (b.channels.empty()) return reject(RejectReason::Shape, "no channels");
  if (b.channels.size() > limits.max_channels) {
    return reject(RejectReason::Shape,
                  std::to_string(b.channels.size()) + " channels, at most " + std::to_string(limits.max_channels));
  }
  for (const auto& c : b.channels) {
    if (c.empty() || c.size() > limits.max_name_bytes)
      return reject(RejectReason::Field, "empty or too long channel name");
  }
  if (!std::isfinite(b.sample_rate_hz) || b.sample_rate_hz <= 0.0) {
    return reject(RejectReason::Field, "sample_rate_hz must be a finite number > 0");
  }
  return std::nullopt;
}

std::optional<ParseResult> check_count(std::size_t n, std::size_t g, const BlockLimits& limits) {
  if (n == 0) return reject(RejectReason::Shape, "no samples");
  if (g != 0 && n > limits.max_values / g) {
    return reject(RejectReason::Oversize, std::to_string(n) + " x " + std::to_string(g) + " values, at most " +
                                              std::to_string(limits.max_values));
  }
  return std::nullopt;
}

}  // namespace detail

using detail::accept;
using detail::check_count;
using detail::check_header;
using detail::reject;

// ---- CSV --------------------------------------------------------------------------------------------------

namespace {

bool parse_double(const std::string& text, double& out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && errno != ERANGE;
}

bool parse_int64(const std::string& text, std::int64_t& out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || errno == ERANGE) return false;
  out = v;
  return true;
}

bool parse_uint64(const std::string& text, std::uint64_t& out) {
  if (text.empty() || text[0] == '-') return false;
  errno = 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || errno == ERANGE) return false;
  out = v;
  return true;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// Fields `split` would return, counted without making them: a line of 16 MiB of commas is 16 M strings
// (about 512 MiB), so a list longer than its limit is refused before it is split.
std::size_t field_count(const std::string& s, std::size_t from, char sep) {
  return 1 + static_cast<std::size_t>(std::count(s.begin() + static_cast<std::ptrdiff_t>(from), s.end(), sep));
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  while (true) {
    const auto end = s.find(sep, begin);
    parts.push_back(trim(s.substr(begin, end == std::string::npos ? std::string::npos : end - begin)));
    if (end == std::string::npos) return parts;
    begin = end + 1;
  }
}

}  // namespace

ParseResult parse_csv_block(const std::string& message, const BlockLimits& limits) {
  if (message.size() > limits.max_bytes)
    return reject(RejectReason::Oversize, "message of " + std::to_string(message.size()) + " bytes");
  // Lines and words are cut out of the message one at a time (no stream holding a copy of it): a message
  // costs itself plus its longest line and word.
  std::size_t at = 0;
  const auto next_line = [&message, &at](std::string& out) {
    if (at >= message.size()) return false;
    const std::size_t end = std::min(message.find('\n', at), message.size());
    out.assign(message, at, end - at);
    at = end + 1;
    return true;
  };
  std::string line;
  next_line(line);
  std::size_t word_at = 0;
  const auto next_word = [&line, &word_at](std::string& out) {
    word_at = line.find_first_not_of(" \t\r\v\f", word_at);
    if (word_at == std::string::npos) return false;
    const std::size_t end = std::min(line.find_first_of(" \t\r\v\f", word_at), line.size());
    out.assign(line, word_at, end - word_at);
    word_at = end;
    return true;
  };
  std::string word;
  next_word(word);
  if (word != kCsvMagic) return reject(RejectReason::Malformed, "CSV block does not start with #block");
  IngestBlock b;
  bool have_rate = false, have_t0 = false, have_seq = false, have_n = false;
  std::uint64_t n = 0;
  while (next_word(word)) {
    const auto eq = word.find('=');
    if (eq == std::string::npos) return reject(RejectReason::Field, "header word '" + word + "' is not key=value");
    const std::string key = word.substr(0, eq);
    const std::string value = key == "channels" ? std::string() : word.substr(eq + 1);
    bool ok = true;
    if (key == "asset_group") {
      b.asset_group = value;
    } else if (key == "channels") {
      // Counted in place, before any copy: the list may be the whole message.
      if (const std::size_t count = field_count(word, eq + 1, ','); count > limits.max_channels) {
        return reject(RejectReason::Shape,
                      std::to_string(count) + " channels, at most " + std::to_string(limits.max_channels));
      }
      b.channels = split(word.substr(eq + 1), ',');
    } else if (key == "unit") {
      b.unit = value;
    } else if (key == "sample_rate_hz") {
      ok = have_rate = parse_double(value, b.sample_rate_hz);
    } else if (key == "t0_ns") {
      ok = have_t0 = parse_int64(value, b.t0_ns);
    } else if (key == "sequence") {
      ok = have_seq = parse_uint64(value, b.sequence);
    } else if (key == "samples") {
      ok = have_n = parse_uint64(value, n);
    } else if (key == "end_of_segment") {
      ok = value == "0" || value == "1";
      b.end_of_segment = value == "1";
    } else {
      return reject(RejectReason::Field, "unknown header key '" + key + "'");
    }
    if (!ok) return reject(RejectReason::Field, "bad value in header word '" + word + "'");
  }
  if (!have_rate || !have_t0 || !have_seq || !have_n) {
    return reject(RejectReason::Field, "header needs sample_rate_hz, t0_ns, sequence and samples");
  }
  if (auto bad = check_header(b, limits)) return *bad;
  const std::size_t g = b.channels.size();
  if (n > limits.max_values) return reject(RejectReason::Oversize, std::to_string(n) + " samples per channel");
  if (auto bad = check_count(static_cast<std::size_t>(n), g, limits)) return *bad;
  b.samples_per_channel = static_cast<std::size_t>(n);
  b.samples.reserve(b.samples_per_channel * g);
  std::size_t row = 0;
  while (row < b.samples_per_channel && next_line(line)) {
    const std::string text = trim(line);
    if (text.empty()) continue;
    if (const std::size_t count = field_count(text, 0, ','); count != g) {
      return reject(RejectReason::Shape, "row " + std::to_string(row) + " has " + std::to_string(count) +
                                             " values, expected " + std::to_string(g));
    }
    const auto values = split(text, ',');
    for (const auto& v : values) {
      double x = 0.0;
      if (!parse_double(v, x))
        return reject(RejectReason::Malformed, "row " + std::to_string(row) + ": '" + v + "' is not a number");
      b.samples.push_back(x);
    }
    ++row;
  }
  if (row < b.samples_per_channel) {
    return reject(RejectReason::Truncated, std::to_string(row) + " of " + std::to_string(n) + " rows");
  }
  while (next_line(line)) {
    if (!trim(line).empty()) return reject(RejectReason::Shape, "more rows than samples=" + std::to_string(n));
  }
  return accept(std::move(b));
}

// ---- binary -----------------------------------------------------------------------------------------------

namespace {

std::uint64_t read_le(const std::string& s, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
  return v;
}

double read_f64(const std::string& s, std::size_t at) {
  const std::uint64_t bits = read_le(s, at, 8);
  double d = 0.0;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

// Fixed header fields and the length of the whole message from its header, when the header (with its
// strings) is complete in `s`. nullopt: more bytes are needed.
struct BinaryLayout {
  std::size_t channels = 0, samples = 0, strings_end = 0;
  std::uint64_t total = 0;
};

std::optional<BinaryLayout> binary_layout(const std::string& s, std::size_t at) {
  if (s.size() - at < kBinaryFixedHeader) return std::nullopt;
  BinaryLayout l;
  l.channels = static_cast<std::size_t>(read_le(s, at + 4, 2));
  l.samples = static_cast<std::size_t>(read_le(s, at + 8, 4));
  std::size_t pos = at + kBinaryFixedHeader;
  for (std::size_t k = 0; k < 2 + l.channels; ++k) {
    if (s.size() < pos + 2) return std::nullopt;
    pos += 2 + static_cast<std::size_t>(read_le(s, pos, 2));
  }
  if (s.size() < pos) return std::nullopt;
  l.strings_end = pos;
  l.total = static_cast<std::uint64_t>(pos - at) + static_cast<std::uint64_t>(l.samples) * l.channels * 8u;
  return l;
}

}  // namespace

ParseResult parse_binary_block(const std::string& m, const BlockLimits& limits) {
  if (m.size() < 4 || m.compare(0, 4, kBinaryMagic) != 0)
    return reject(RejectReason::Malformed, "binary block without CTB1 magic");
  if (m.size() < kBinaryFixedHeader)
    return reject(RejectReason::Truncated, "binary header of " + std::to_string(m.size()) + " bytes");
  IngestBlock b;
  const std::size_t g = static_cast<std::size_t>(read_le(m, 4, 2));
  const auto flags = read_le(m, 6, 2);
  const std::size_t n = static_cast<std::size_t>(read_le(m, 8, 4));
  b.sequence = read_le(m, 12, 8);
  b.t0_ns = static_cast<std::int64_t>(read_le(m, 20, 8));
  b.sample_rate_hz = read_f64(m, 28);
  b.end_of_segment = (flags & 1u) != 0;
  if (g == 0) return reject(RejectReason::Shape, "no channels");
  if (g > limits.max_channels)
    return reject(RejectReason::Shape, std::to_string(g) + " channels, at most " + std::to_string(limits.max_channels));
  if (auto bad = check_count(n, g, limits)) return *bad;
  std::size_t pos = kBinaryFixedHeader;
  std::vector<std::string> strings;
  for (std::size_t k = 0; k < 2 + g; ++k) {
    if (m.size() < pos + 2) return reject(RejectReason::Truncated, "binary header ends inside its names");
    const auto len = static_cast<std::size_t>(read_le(m, pos, 2));
    pos += 2;
    if (m.size() < pos + len) return reject(RejectReason::Truncated, "binary header ends inside its names");
    strings.push_back(m.substr(pos, len));
    pos += len;
  }
  b.asset_group = strings[0];
  b.unit = strings[1];
  b.channels.assign(strings.begin() + 2, strings.end());
  if (auto bad = check_header(b, limits)) return *bad;
  const std::size_t want = n * g * 8;
  if (m.size() - pos < want) {
    return reject(RejectReason::Truncated,
                  std::to_string(m.size() - pos) + " of " + std::to_string(want) + " sample bytes");
  }
  if (m.size() - pos > want)
    return reject(RejectReason::Shape, std::to_string(m.size() - pos - want) + " bytes after the samples");
  b.samples_per_channel = n;
  b.samples.resize(n * g);
  for (std::size_t i = 0; i < n * g; ++i) b.samples[i] = read_f64(m, pos + 8 * i);
  return accept(std::move(b));
}

ParseResult parse_block(const std::string& message, const BlockLimits& limits) {
  if (message.size() > limits.max_bytes)
    return reject(RejectReason::Oversize, "message of " + std::to_string(message.size()) + " bytes");
  const auto first = message.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return reject(RejectReason::Malformed, "empty message");
  if (message.compare(0, 4, kBinaryMagic) == 0) return parse_binary_block(message, limits);
  if (message[first] == '{') return parse_json_block(message, limits);
  if (message.compare(first, 6, kCsvMagic) == 0) return parse_csv_block(message.substr(first), limits);
  return reject(RejectReason::Malformed, "neither JSON ('{'), CSV ('#block') nor binary ('CTB1')");
}

// ---- stream splitting --------------------------------------------------------------------------------------

std::optional<std::string> BlockStreamSplitter::next(bool eof) {
  // Compact now and then so the buffer does not grow with the stream.
  if (start_ > (1u << 20) && start_ > buffer_.size() / 2) {
    buffer_.erase(0, start_);
    start_ = 0;
  }
  if (skip_ > 0) {
    const std::size_t drop = std::min<std::uint64_t>(skip_, buffer_.size() - start_);
    start_ += drop;
    skip_ -= drop;
    if (skip_ > 0) return std::nullopt;
  }
  while (start_ < buffer_.size() && std::strchr(" \t\r\n", buffer_[start_]) != nullptr) ++start_;
  if (start_ >= buffer_.size()) return std::nullopt;
  const auto take = [this](std::size_t end) {
    std::string m = buffer_.substr(start_, end - start_);
    start_ = end;
    return m;
  };
  const auto line_end = [this](std::size_t from) { return buffer_.find('\n', from); };
  const std::size_t available = buffer_.size() - start_;
  if (buffer_.compare(start_, 4, kBinaryMagic) == 0 ||
      (available < 4 && std::string(kBinaryMagic).compare(0, available, buffer_, start_, available) == 0 && !eof)) {
    const auto layout = binary_layout(buffer_, start_);
    if (!layout) return eof ? std::optional<std::string>(take(buffer_.size())) : std::nullopt;
    if (layout->total > limits_.max_bytes || layout->samples * layout->channels > limits_.max_values) {
      // Too big to hold: hand over the header (rejected as oversize) and drop the rest unread.
      std::string header = take(layout->strings_end);
      skip_ = layout->total - header.size();
      return header;
    }
    if (available < layout->total) return eof ? std::optional<std::string>(take(buffer_.size())) : std::nullopt;
    return take(start_ + static_cast<std::size_t>(layout->total));
  }
  if (buffer_.compare(start_, 6, kCsvMagic) == 0) {
    const auto header_end = line_end(start_);
    if (header_end == std::string::npos) return eof ? std::optional<std::string>(take(buffer_.size())) : std::nullopt;
    // The number of rows from the header's samples= word; without a usable one the header alone is the message.
    const std::string header = buffer_.substr(start_, header_end - start_);
    std::uint64_t rows = 0;
    const auto at = header.find(" samples=");
    bool counted = false;
    if (at != std::string::npos) {
      const auto value_end = header.find_first_of(" \t\r", at + 9);
      counted =
          parse_uint64(header.substr(at + 9, value_end == std::string::npos ? std::string::npos : value_end - at - 9),
                       rows) &&
          rows <= limits_.max_values;
    }
    if (!counted) return take(header_end + 1);
    std::size_t pos = header_end + 1;
    for (std::uint64_t r = 0; r < rows; ++r) {
      // Blank lines do not count as rows (the parser skips them too).
      std::size_t end = line_end(pos);
      while (end != std::string::npos && trim(buffer_.substr(pos, end - pos)).empty()) {
        pos = end + 1;
        end = line_end(pos);
      }
      if (end == std::string::npos) {
        if (!eof) return std::nullopt;
        return take(buffer_.size());
      }
      pos = end + 1;
    }
    return take(pos);
  }
  // JSON line, or bytes that start nothing known: up to the line end (or the next binary magic).
  auto end = line_end(start_);
  if (buffer_[start_] != '{') end = std::min(end, buffer_.find(kBinaryMagic, start_ + 1));
  if (end == std::string::npos) {
    if (!eof && available <= limits_.max_bytes) return std::nullopt;
    return take(buffer_.size());
  }
  return take(end);
}

}  // namespace causal::ingest
