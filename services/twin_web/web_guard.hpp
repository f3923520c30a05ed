// twin-web's request checks, kept free of HTTP library types so they are unit-tested on their own:
//  * Host: only a name this server answers to (loopback names, this machine's name, an IP literal, or one
//    given with --allowed-host). A DNS-rebinding page reaches the server under the attacker's domain name,
//    so its requests carry that name and are refused, reads included.
//  * Origin on every state-changing request: absent (a non-browser client) or the same scheme://host:port
//    the request was sent to; a browser always sends it on a cross-site POST, so a forged one is refused.
//    Sec-Fetch-Site "cross-site" is refused too.
//  * A CSRF token on every state-changing request (X-Twin-CSRF header), random per process and handed out
//    only inside the page (the same-origin policy keeps other sites from reading it).
//  * Optional HTTP basic authentication (credentials file) for every request.
#pragma once

#include <string>
#include <vector>

namespace causal::web {

struct GuardOptions {
  std::vector<std::string> allowed_hosts;  // extra Host names (no port), e.g. "twin.plant.example"
  std::string basic_user;                  // "" = no authentication
  std::string basic_password;
  bool tls = false;                        // the server speaks HTTPS (the origin's scheme)
};

// What a request carries that the checks look at ("" = header absent).
struct RequestFacts {
  std::string method;
  std::string host;            // Host header
  std::string origin;          // Origin header
  std::string fetch_site;      // Sec-Fetch-Site header
  std::string csrf_token;      // X-Twin-CSRF header
  std::string authorization;   // Authorization header
};

struct Verdict {
  int status = 0;       // 0 = allowed, else the HTTP status to answer with (401, 403, 421)
  std::string reason;   // why, for the log and the body; also the refusal counter's label
  std::string detail;   // the offending value, for the log
};

class RequestGuard {
 public:
  // `csrf_token` "" = a fresh random one (32 hex digits from /dev/urandom).
  explicit RequestGuard(GuardOptions options, std::string csrf_token = {});

  Verdict check(const RequestFacts& request) const;
  const std::string& csrf_token() const { return csrf_token_; }
  bool authenticating() const { return !expected_authorization_.empty(); }
  const std::string& user() const { return options_.basic_user; }  // the authenticated user ("" none)

  // The host part of a Host header value (brackets kept for IPv6, port dropped), lower case.
  static std::string host_name_of(const std::string& host_header);
  static bool is_ip_literal(const std::string& host);

 private:
  bool host_allowed(const std::string& host_header) const;

  GuardOptions options_;
  std::string csrf_token_;
  std::string expected_authorization_;  // "Basic base64(user:password)"
  std::vector<std::string> names_;      // allowed names, lower case
};

// Reads "USER:PASSWORD" (first line) from a file that only its owner may read; throws std::invalid_argument
// naming the file and the problem otherwise.
void read_basic_auth_file(const std::string& path, std::string& user, std::string& password);

// The headers every response carries: a Content-Security-Policy that allows only this origin's scripts,
// styles and connections and no framing (frame-ancestors 'none', X-Frame-Options DENY), no MIME sniffing,
// no referrer.
std::vector<std::pair<std::string, std::string>> security_headers();

}  // namespace causal::web
