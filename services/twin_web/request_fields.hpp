// The fields every POST body of the page shares (an alarm action, an approval): string fields bounded in bytes,
// the ids a request names, and who acts. With basic authentication the one who acts is the authenticated user
// (a body cannot act in another's name); without, the body's "user".
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace causal::web {

// The string field `key` of `body`: "" when absent; false when present but not a string or too long.
bool text_field(const nlohmann::json& body, const char* key, std::size_t max_bytes, std::string& out);
// A required id (an asset group, an alarm, a recommendation; at most dds::kMaxIdBytes): "" or the problem.
std::string required_id(const nlohmann::json& body, const char* key, std::string& out);
// Who acts: "" or the problem.
std::string acting_user(const nlohmann::json& body, const std::string& authenticated_user, std::string& user);

}  // namespace causal::web
