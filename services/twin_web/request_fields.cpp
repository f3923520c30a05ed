#include "request_fields.hpp"

#include "causal/dds/sample_limits.hpp"

namespace causal::web {

bool text_field(const nlohmann::json& body, const char* key, std::size_t max_bytes, std::string& out) {
  out.clear();
  if (!body.contains(key)) return true;
  if (!body[key].is_string()) return false;
  out = body[key].get<std::string>();
  return out.size() <= max_bytes;
}

std::string required_id(const nlohmann::json& body, const char* key, std::string& out) {
  if (!text_field(body, key, dds::kMaxIdBytes, out) || out.empty()) return std::string(key) + " (string) is required";
  return {};
}

std::string acting_user(const nlohmann::json& body, const std::string& authenticated_user, std::string& user) {
  if (!text_field(body, "user", 64, user)) return "user must be a string of at most 64 bytes";
  if (!authenticated_user.empty()) user = authenticated_user;
  if (user.empty()) return "user (string) is required";
  return {};
}

}  // namespace causal::web
