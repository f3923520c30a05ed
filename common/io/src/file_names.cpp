#include "causal/io/file_names.hpp"

#include <cstdint>
#include <cstdio>

namespace causal::io {

std::string safe_file_component(const std::string& id) {
  std::string out;
  bool replaced = id.empty();
  for (char c : id) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                      c == '-' || c == '_';
    out += keep ? c : '_';
    replaced = replaced || !keep;
  }
  if (!out.empty() && out[0] == '.') {
    out[0] = '_';
    replaced = true;
  }
  if (replaced) {
    std::uint32_t h = 2166136261u;  // FNV-1a 32 of the original id: distinct ids, distinct files
    for (unsigned char c : id) h = (h ^ c) * 16777619u;
    char hex[10];
    std::snprintf(hex, sizeof hex, "-%08x", h);
    out += hex;
  }
  if (out.size() > kMaxFileComponentBytes) {
    std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64 of the original id
    for (unsigned char c : id) h = (h ^ c) * 1099511628211ull;
    char hex[18];
    std::snprintf(hex, sizeof hex, "-%016llx", static_cast<unsigned long long>(h));
    out.resize(kMaxFileComponentBytes - 17);
    out += hex;
  }
  return out;
}

}  // namespace causal::io
