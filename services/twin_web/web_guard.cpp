#include "web_guard.hpp"

#include <arpa/inet.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <stdexcept>

namespace causal::web {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// Compares in time independent of where the first difference is (tokens and passwords).
bool equal_constant_time(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  const std::size_t n = std::max(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    diff |= static_cast<unsigned char>(x ^ y);
  }
  return diff == 0;
}

std::string base64(const std::string& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += table[(v >> s) & 63];
  }
  if (i < in.size()) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < in.size() ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string random_token() {
  std::ifstream urandom("/dev/urandom", std::ios::binary);
  unsigned char bytes[16] = {};
  if (!urandom.read(reinterpret_cast<char*>(bytes), sizeof bytes)) {
    throw std::runtime_error("cannot read /dev/urandom for the CSRF token");
  }
  static const char* hex = "0123456789abcdef";
  std::string t;
  for (unsigned char b : bytes) {
    t += hex[b >> 4];
    t += hex[b & 15];
  }
  return t;
}

bool state_changing(const std::string& method) { return method != "GET" && method != "HEAD" && method != "OPTIONS"; }

}  // namespace

RequestGuard::RequestGuard(GuardOptions options, std::string csrf_token)
    : options_(std::move(options)), csrf_token_(csrf_token.empty() ? random_token() : std::move(csrf_token)) {
  if (!options_.basic_user.empty()) {
    expected_authorization_ = "Basic " + base64(options_.basic_user + ":" + options_.basic_password);
  }
  names_ = {"localhost"};
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0 && host[0] != '\0') names_.push_back(lower(host));
  for (const auto& h : options_.allowed_hosts) names_.push_back(lower(h));
}

std::string RequestGuard::host_name_of(const std::string& host_header) {
  std::string h = lower(host_header);
  if (!h.empty() && h.front() == '[') {
    const auto close = h.find(']');
    return close == std::string::npos ? h : h.substr(0, close + 1);
  }
  const auto colon = h.find(':');
  return colon == std::string::npos ? h : h.substr(0, colon);
}

bool RequestGuard::is_ip_literal(const std::string& host) {
  unsigned char buf[sizeof(struct in6_addr)];
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    return inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), buf) == 1;
  }
  return inet_pton(AF_INET, host.c_str(), buf) == 1;
}

bool RequestGuard::host_allowed(const std::string& host_header) const {
  const std::string name = host_name_of(host_header);
  if (name.empty()) return false;
  // An IP literal cannot be rebound: a page served under the attacker's name never sends one.
  if (is_ip_literal(name)) return true;
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

Verdict RequestGuard::check(const RequestFacts& r) const {
  if (!host_allowed(r.host)) {
    return {421, "host_not_allowed", "Host '" + r.host + "' (allow it with --allowed-host)"};
  }
  if (authenticating() && !equal_constant_time(r.authorization, expected_authorization_)) {
    return {401, "unauthenticated", r.authorization.empty() ? "no credentials" : "wrong credentials"};
  }
  if (!state_changing(r.method)) return {};
  if (lower(r.fetch_site) == "cross-site") return {403, "cross_origin", "Sec-Fetch-Site: cross-site"};
  if (!r.origin.empty()) {
    const std::string own = (options_.tls ? "https://" : "http://") + lower(r.host);
    if (lower(r.origin) != own) return {403, "cross_origin", "Origin '" + r.origin + "' on a request to " + own};
  }
  if (!equal_constant_time(r.csrf_token, csrf_token_)) {
    return {403, "csrf_token", r.csrf_token.empty() ? "no X-Twin-CSRF token (reload the page)"
                                                    : "wrong X-Twin-CSRF token (reload the page)"};
  }
  return {};
}

void read_basic_auth_file(const std::string& path, std::string& user, std::string& password) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) throw std::invalid_argument("--basic-auth-file " + path + ": cannot read it");
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    throw std::invalid_argument("--basic-auth-file " + path + ": readable by others (chmod 600 it)");
  }
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n' || line.back() == ' ')) line.pop_back();
  const auto colon = line.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 >= line.size()) {
    throw std::invalid_argument("--basic-auth-file " + path + ": expected one line USER:PASSWORD");
  }
  user = line.substr(0, colon);
  password = line.substr(colon + 1);
  if (password.size() < 12) throw std::invalid_argument("--basic-auth-file " + path + ": password under 12 characters");
}

std::vector<std::pair<std::string, std::string>> security_headers() {
  return {{"Content-Security-Policy",
           "default-src 'none'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
           "connect-src 'self'; font-src 'self'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'"},
          {"X-Frame-Options", "DENY"},
          {"X-Content-Type-Options", "nosniff"},
          {"Referrer-Policy", "no-referrer"},
          {"Cross-Origin-Opener-Policy", "same-origin"},
          {"Cross-Origin-Resource-Policy", "same-origin"}};
}

}  // namespace causal::web
