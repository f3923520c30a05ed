#include "feature_row.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>

namespace causal::ingest {

namespace {

constexpr const char* kCsvMagic = "#features";

FeatureParseResult reject(RejectReason reason, std::string detail) {
  FeatureParseResult r;
  r.reason = reason;
  r.detail = std::move(detail);
  return r;
}

// At most max_items + 1 items are kept (one more than allowed, so the shape check can refuse with the count): a
// 16 MiB list of separators never becomes millions of strings.
std::vector<std::string> split(const std::string& s, char sep, std::size_t max_items) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (out.size() <= max_items && std::getline(in, item, sep)) out.push_back(item);
  return out;
}

// The checks both encodings share: names, shape, limits.
FeatureParseResult check(FeatureRow row, const BlockLimits& limits) {
  if (row.asset_group.empty() || row.asset_group.size() > limits.max_name_bytes)
    return reject(RejectReason::Field, "asset_group missing or longer than " + std::to_string(limits.max_name_bytes));
  if (row.feature.empty() || row.feature.size() > limits.max_name_bytes)
    return reject(RejectReason::Field, "feature missing or too long");
  if (row.channels.empty()) return reject(RejectReason::Shape, "no channels");
  if (row.channels.size() > limits.max_channels)
    return reject(RejectReason::Shape, std::to_string(row.channels.size()) + " channels (at most " +
                                           std::to_string(limits.max_channels) + ")");
  for (const auto& c : row.channels) {
    if (c.empty() || c.size() > limits.max_name_bytes) return reject(RejectReason::Field, "empty or too long channel name");
  }
  if (row.values.size() != row.channels.size())
    return reject(RejectReason::Shape, std::to_string(row.values.size()) + " values for " +
                                           std::to_string(row.channels.size()) + " channels");
  for (double v : row.values) row.non_finite += std::isfinite(v) ? 0 : 1;
  FeatureParseResult r;
  r.row = std::move(row);
  return r;
}

// A feature row decoded by events (nlohmann's SAX interface), never into a document tree, like the raw JSON blocks
// (json_block.cpp): the row has two levels (the object and its arrays), so anything deeper is refused at once; the
// arrays keep at most max_channels + 1 entries (one more than allowed, so the shape check can name the count); a
// key that appears twice is refused (RFC 8259, section 4: the meaning of such a message depends on the parser).
class FeatureRowEvents {
 public:
  using json = nlohmann::json;
  explicit FeatureRowEvents(const BlockLimits& limits) : limits_(limits) {}

  bool null() { return value(NAN, false); }
  bool boolean(bool v) {
    if (depth_ == 1 && key_ == "discontinuity") return row_.discontinuity = v, true;
    return other();
  }
  bool number_integer(json::number_integer_t v) {
    if (depth_ == 1 && key_ == "time_ns") return row_.time_ns = v, has_time_ = true;
    if (depth_ == 1 && key_ == "sequence") {
      if (v < 0) return stop(RejectReason::Field, "sequence is negative");
      return row_.sequence = static_cast<std::uint64_t>(v), has_sequence_ = true;
    }
    return value(static_cast<double>(v), true);
  }
  bool number_unsigned(json::number_unsigned_t v) {
    if (depth_ == 1 && key_ == "time_ns") {
      if (v > static_cast<std::uint64_t>(INT64_MAX)) return stop(RejectReason::Field, "time_ns out of range");
      return row_.time_ns = static_cast<std::int64_t>(v), has_time_ = true;
    }
    if (depth_ == 1 && key_ == "sequence") return row_.sequence = v, has_sequence_ = true;
    return value(static_cast<double>(v), true);
  }
  bool number_float(json::number_float_t v, const json::string_t& /*text*/) {
    if (depth_ == 1 && (key_ == "time_ns" || key_ == "sequence")) return stop(RejectReason::Field, key_ + " is not an integer");
    return value(v, true);
  }
  bool string(json::string_t& v) {
    if (depth_ == 1 && key_ == "asset_group") return row_.asset_group = std::move(v), true;
    if (depth_ == 1 && key_ == "feature") return row_.feature = std::move(v), true;
    if (depth_ == 2 && key_ == "channels") {
      if (row_.channels.size() > limits_.max_channels) return stop(RejectReason::Shape, "more than " + std::to_string(limits_.max_channels) + " channels");
      return row_.channels.push_back(std::move(v)), true;
    }
    return other();
  }
  bool binary(json::binary_t& /*v*/) { return other(); }
  bool start_object(std::size_t /*n*/) {
    if (depth_ >= 1) return stop(RejectReason::Field, "'" + key_ + "' is an object (a feature row holds none)");
    return open();
  }
  bool start_array(std::size_t /*n*/) {
    if (depth_ == 1 && key_ != "channels" && key_ != "values") return stop(RejectReason::Field, "'" + key_ + "' is an array");
    return open();
  }
  bool end_object() { return --depth_, true; }
  bool end_array() { return --depth_, true; }
  bool key(json::string_t& k) {
    if (!keys_.insert(k).second) return stop(RejectReason::Malformed, "duplicate key '" + k + "'");
    key_ = std::move(k);
    return true;
  }
  bool parse_error(std::size_t /*position*/, const std::string& /*token*/, const nlohmann::detail::exception&) {
    return false;
  }

  const std::optional<FeatureParseResult>& stopped() const { return stopped_; }
  FeatureParseResult finish() {
    if (!has_time_ || !has_sequence_) return reject(RejectReason::Field, "time_ns and sequence are required");
    return check(std::move(row_), limits_);
  }

 private:
  bool stop(RejectReason reason, std::string detail) {
    stopped_ = reject(reason, std::move(detail));
    return false;
  }
  bool open() {
    if (++depth_ > 2) return stop(RejectReason::Malformed, "nested deeper than a feature row (an object of arrays)");
    if (depth_ == 1 && opened_top_) return stop(RejectReason::Malformed, "more than one object");
    opened_top_ = opened_top_ || depth_ == 1;
    return true;
  }
  bool value(double v, bool number) {
    if (depth_ == 2 && key_ == "values") {
      if (row_.values.size() > limits_.max_channels) return stop(RejectReason::Shape, "more than " + std::to_string(limits_.max_channels) + " values");
      row_.values.push_back(number ? v : NAN);
      return true;
    }
    return other();
  }
  bool other() {
    if (depth_ == 0) return stop(RejectReason::Malformed, "not a JSON object");
    if (depth_ == 2 || key_ == "asset_group" || key_ == "feature" || key_ == "time_ns" || key_ == "sequence" ||
        key_ == "discontinuity" || key_ == "channels" || key_ == "values")
      return stop(RejectReason::Field, "feature row: '" + key_ + "' has the wrong type");
    return true;  // an extra top-level scalar: ignored, as before
  }

  const BlockLimits& limits_;
  FeatureRow row_;
  std::set<std::string> keys_;  // top-level keys only: depth 2 holds no objects
  std::string key_;
  int depth_ = 0;
  bool opened_top_ = false;
  bool has_time_ = false, has_sequence_ = false;
  std::optional<FeatureParseResult> stopped_;
};

FeatureParseResult parse_json(const std::string& message, const BlockLimits& limits) {
  FeatureRowEvents events(limits);
  const bool parsed = nlohmann::json::sax_parse(message, &events, nlohmann::json::input_format_t::json,
                                                /*strict=*/true);
  if (!parsed) return events.stopped() ? *events.stopped() : reject(RejectReason::Malformed, "not valid JSON");
  return events.finish();
}

FeatureParseResult parse_csv(const std::string& message, const BlockLimits& limits) {
  std::istringstream words(message.substr(message.find(kCsvMagic) + 9));
  FeatureRow row;
  bool has_time = false, has_sequence = false;
  std::set<std::string> seen;
  std::string word;
  try {
    while (words >> word) {
      const auto eq = word.find('=');
      if (eq == std::string::npos) return reject(RejectReason::Malformed, "'" + word + "' is not key=value");
      const std::string key = word.substr(0, eq), value = word.substr(eq + 1);
      if (!seen.insert(key).second) return reject(RejectReason::Malformed, "duplicate key '" + key + "'");
      std::size_t used = 0;
      if (key == "asset_group") row.asset_group = value;
      else if (key == "feature") row.feature = value;
      else if (key == "channels") row.channels = split(value, ',', limits.max_channels);
      else if (key == "time_ns") row.time_ns = std::stoll(value, &used), has_time = used == value.size();
      else if (key == "sequence") row.sequence = std::stoull(value, &used), has_sequence = used == value.size();
      else if (key == "discontinuity") row.discontinuity = value == "1" || value == "true";
      else if (key == "values") {
        for (const auto& v : split(value, ',', limits.max_channels)) row.values.push_back(v == "nan" ? NAN : std::stod(v));
      } else {
        return reject(RejectReason::Field, "unknown key '" + key + "'");
      }
    }
  } catch (const std::exception&) {
    return reject(RejectReason::Malformed, "a number that is not one in '" + word + "'");
  }
  if (!has_time || !has_sequence) return reject(RejectReason::Field, "time_ns and sequence are required");
  return check(std::move(row), limits);
}

}  // namespace

bool is_feature_row(const std::string& message) {
  const auto first = message.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return false;
  if (message.compare(first, 9, kCsvMagic) == 0) return true;
  return message[first] == '{' && message.find("\"values\"") != std::string::npos &&
         message.find("\"samples\"") == std::string::npos;
}

FeatureParseResult parse_feature_row(const std::string& message, const BlockLimits& limits) {
  if (message.size() > limits.max_bytes)
    return reject(RejectReason::Oversize, "message of " + std::to_string(message.size()) + " bytes");
  const auto first = message.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && message[first] == '{') return parse_json(message, limits);
  return parse_csv(message.substr(first == std::string::npos ? 0 : first), limits);
}

}  // namespace causal::ingest
