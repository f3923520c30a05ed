// The product's HTTP server, for twin-web's live view and every service's /metrics endpoint: GNU libmicrohttpd
// (one epoll polling thread, bounded connections) behind a small request/response pair and a route table, so
// route handlers do not depend on the server library.
//
// A route is registered as:  server.Get("/api/x", [](const HttpRequest& req, HttpResponse& res) {...});
// (Post likewise). Handlers run on a worker pool, never on the polling thread, so a handler may wait (a what-if
// question waits for its reply; an event stream waits for the next change) without stalling other clients.
//
// Limits (a slow or greedy client cannot starve or blow up the process):
//  * header bytes: the per-connection memory pool (kConnectionMemoryBytes); header count: kMaxHeaders (431);
//  * connections: kMaxConnections in all, kMaxConnectionsPerAddress per client address;
//  * a connection idle (or trickling slower than one byte per timeout) for kIdleTimeoutS is closed;
//  * bodies: compressed ones are refused unread (415), more than kMaxBodyBytes too (413);
//  * queries: kMaxQueryParams arguments of kMaxQueryArgumentBytes, UTF-8 (400 bad_query);
//  * a handler that throws answers its request 500 (handler_error), the process goes on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <regex>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace causal::http {

constexpr std::size_t kMaxBodyBytes = 64 * 1024;  // the largest request body taken (a what-if question: ~100 B)
constexpr std::size_t kMaxHeaders = 100;
constexpr std::size_t kConnectionMemoryBytes = 64 * 1024;
constexpr unsigned kMaxConnections = 512;
constexpr unsigned kMaxConnectionsPerAddress = 64;
constexpr unsigned kIdleTimeoutS = 10;
// A request (its headers and body) must arrive within this many seconds of the connection's start or of the
// previous response: a client that trickles one byte a second is never idle, so only this closes it.
constexpr unsigned kRequestDeadlineS = 15;
// The query: at most this many arguments, each (name and value, decoded) at most this long and UTF-8; else 400
// bad_query before any handler sees it (a handler may echo a value into JSON, which must be UTF-8).
constexpr std::size_t kMaxQueryParams = 16;
constexpr std::size_t kMaxQueryArgumentBytes = 1024;

struct HttpRequest {
  std::string method;       // GET, HEAD, POST, ...
  std::string path;         // without the query
  std::string remote_addr;  // the client's address
  std::string body;
  std::map<std::string, std::string> headers;  // names in lower case
  std::map<std::string, std::string> params;   // the query, decoded
  std::vector<std::string> matches;            // a pattern route's captures ([0]: the whole path), as std::smatch

  std::string get_header_value(const std::string& name) const;  // "" when absent (name in any case)
  bool has_param(const std::string& name) const { return params.count(name) != 0; }
  std::string get_param_value(const std::string& name) const;
};

// A chunk writer for a streamed response: false once the client is gone (stop streaming).
using StreamSink = std::function<bool(const std::string& chunk)>;
// Called again and again on a worker thread while it returns true.
using StreamProvider = std::function<bool(const StreamSink& sink)>;

struct HttpResponse {
  int status = 200;
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;
  StreamProvider stream;          // set: a chunked response written by stream (body unused)
  std::function<void()> on_done;  // with stream: called once the stream ends

  void set_header(const std::string& name, const std::string& value) { headers.emplace_back(name, value); }
  void set_content(std::string content, const std::string& content_type);
  void set_chunked_content_provider(const std::string& content_type, StreamProvider provider,
                                    std::function<void()> done);
};

using HttpHandler = std::function<void(const HttpRequest&, HttpResponse&)>;
// Runs on every request before routing (on the polling thread: keep it cheap, never wait). Returns true when it
// answered the request itself (a refusal).
using PreRoutingHandler = std::function<bool(const HttpRequest&, HttpResponse&)>;

struct ServerTls {
  std::string cert_pem;  // both empty: plain HTTP
  std::string key_pem;
};

class HttpServer {
 public:
  explicit HttpServer(ServerTls tls, std::size_t workers);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // path: exact, or an ECMAScript pattern matched against the whole path (e.g. R"(/api/alarms/([^/]+)/ack)"),
  // its captures in HttpRequest::matches; exact paths are looked up first.
  void Get(const std::string& path, HttpHandler handler);  // also answers HEAD
  void Post(const std::string& path, HttpHandler handler);
  void set_pre_routing_handler(PreRoutingHandler handler) { pre_routing_ = std::move(handler); }
  // Told of every refusal the server makes itself (reason, detail): too_many_headers, body_too_large (a chunked
  // body), request_deadline, bad_query, handler_error. Called on the polling thread, the deadline thread or a
  // worker.
  void set_refusal_observer(std::function<void(const std::string&, const std::string&)> observer) {
    on_refusal_ = std::move(observer);
  }
  void set_default_headers(std::vector<std::pair<std::string, std::string>> headers) {
    default_headers_ = std::move(headers);
  }
  // Binds and starts serving (its own polling thread). Returns the port, 0 when it cannot listen.
  int listen(const std::string& address, int port);
  void stop();  // ends every stream and waiting handler, then closes the socket

  struct Impl;

 private:
  const HttpHandler* route(HttpRequest& req) const;  // fills req.matches for a pattern route; null: none

  std::unique_ptr<Impl> impl_;
  PreRoutingHandler pre_routing_;
  std::function<void(const std::string&, const std::string&)> on_refusal_;
  std::vector<std::pair<std::string, std::string>> default_headers_;
  std::map<std::string, HttpHandler> get_routes_;
  std::map<std::string, HttpHandler> post_routes_;
  std::vector<std::pair<std::regex, const HttpHandler*>> get_patterns_;  // into the maps above
  std::vector<std::pair<std::regex, const HttpHandler*>> post_patterns_;
  friend struct Impl;
};

}  // namespace causal::http
