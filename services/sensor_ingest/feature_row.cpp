#include "feature_row.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
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

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
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

FeatureParseResult parse_json(const std::string& message, const BlockLimits& limits) {
  // Depth at most 2 (the object and its arrays): nothing deeper is ever needed, so nothing deeper is parsed.
  const auto shallow = [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) { return depth <= 2; };
  const nlohmann::json j = nlohmann::json::parse(message, shallow, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return reject(RejectReason::Malformed, "not a JSON object");
  FeatureRow row;
  try {
    row.asset_group = j.at("asset_group").get<std::string>();
    row.feature = j.at("feature").get<std::string>();
    row.channels = j.at("channels").get<std::vector<std::string>>();
    row.time_ns = j.at("time_ns").get<std::int64_t>();
    row.sequence = j.at("sequence").get<std::uint64_t>();
    for (const auto& v : j.at("values")) row.values.push_back(v.is_null() ? NAN : v.get<double>());
    if (j.contains("discontinuity")) row.discontinuity = j.at("discontinuity").get<bool>();
  } catch (const std::exception& e) {
    return reject(RejectReason::Field, std::string("feature row: ") + e.what());
  }
  return check(std::move(row), limits);
}

FeatureParseResult parse_csv(const std::string& message, const BlockLimits& limits) {
  std::istringstream words(message.substr(message.find(kCsvMagic) + 9));
  FeatureRow row;
  bool has_time = false, has_sequence = false;
  std::string word;
  try {
    while (words >> word) {
      const auto eq = word.find('=');
      if (eq == std::string::npos) return reject(RejectReason::Malformed, "'" + word + "' is not key=value");
      const std::string key = word.substr(0, eq), value = word.substr(eq + 1);
      std::size_t used = 0;
      if (key == "asset_group") row.asset_group = value;
      else if (key == "feature") row.feature = value;
      else if (key == "channels") row.channels = split(value, ',');
      else if (key == "time_ns") row.time_ns = std::stoll(value, &used), has_time = used == value.size();
      else if (key == "sequence") row.sequence = std::stoull(value, &used), has_sequence = used == value.size();
      else if (key == "discontinuity") row.discontinuity = value == "1" || value == "true";
      else if (key == "values") {
        for (const auto& v : split(value, ',')) row.values.push_back(v == "nan" ? NAN : std::stod(v));
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
