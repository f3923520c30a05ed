#include "causal/http/http_server.hpp"

#include <microhttpd.h>

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <unordered_map>
#include <mutex>
#include <thread>

namespace causal::http {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The bytes a streamed response may hold for a client that does not read: the writer waits beyond this.
constexpr std::size_t kMaxStreamBuffer = 256 * 1024;

// One streamed response: the worker writes, the polling thread's content reader sends. While there is nothing
// to send the connection is suspended (no busy polling); a write resumes it.
struct Stream {
  std::mutex m;
  std::condition_variable cv;
  std::string buffer;
  bool done = false;       // the writer has finished
  bool closed = false;     // the connection has finished with the response
  bool suspended = false;  // suspended by the content reader, waiting for a write
  MHD_Connection* connection = nullptr;
};

// One request from its headers to its response.
struct Exchange {
  HttpRequest request;
  HttpResponse response;
  const HttpHandler* handler = nullptr;
  bool too_large = false;
  bool dispatched = false;
  std::atomic<bool> ready{false};
};

MHD_Result collect_header(void* cls, MHD_ValueKind, const char* key, const char* value) {
  auto& headers = *static_cast<std::map<std::string, std::string>*>(cls);
  headers.emplace(lower(key ? key : ""), value ? value : "");  // the first of repeated names, as before
  return MHD_YES;
}

MHD_Result collect_param(void* cls, MHD_ValueKind, const char* key, const char* value) {
  auto& params = *static_cast<std::map<std::string, std::string>*>(cls);
  if (key) params.emplace(key, value ? value : "");
  return MHD_YES;
}

// Well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, nothing past U+10FFFF).
bool valid_utf8(const std::string& text) {
  const auto* p = reinterpret_cast<const unsigned char*>(text.data());
  const auto* end = p + text.size();
  while (p < end) {
    const unsigned c = *p++;
    if (c < 0x80) continue;
    int more = 0;
    unsigned low = 0x80, high = 0xBF;  // the range of the first continuation byte
    if (c >= 0xC2 && c <= 0xDF) {
      more = 1;
    } else if (c >= 0xE0 && c <= 0xEF) {
      more = 2;
      if (c == 0xE0) low = 0xA0;
      if (c == 0xED) high = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      more = 3;
      if (c == 0xF0) low = 0x90;
      if (c == 0xF4) high = 0x8F;
    } else {
      return false;
    }
    for (int i = 0; i < more; ++i, low = 0x80, high = 0xBF) {
      if (p >= end || *p < low || *p > high) return false;
      ++p;
    }
  }
  return true;
}

// What is wrong with a request's query ("" when nothing): too many arguments, one too long, not UTF-8.
std::string query_problem(const std::map<std::string, std::string>& params, std::size_t count) {
  if (count > kMaxQueryParams) return "more than " + std::to_string(kMaxQueryParams) + " query arguments";
  for (const auto& [key, value] : params) {
    if (key.size() + value.size() > kMaxQueryArgumentBytes) {
      return "a query argument longer than " + std::to_string(kMaxQueryArgumentBytes) + " bytes";
    }
    if (!valid_utf8(key) || !valid_utf8(value)) return "a query argument that is not UTF-8";
  }
  return {};
}

std::string client_address(MHD_Connection* connection) {
  const MHD_ConnectionInfo* info = MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
  if (!info || !info->client_addr) return {};
  char text[INET6_ADDRSTRLEN] = "";
  if (info->client_addr->sa_family == AF_INET) {
    inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(info->client_addr)->sin_addr, text, sizeof text);
  } else if (info->client_addr->sa_family == AF_INET6) {
    inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(info->client_addr)->sin6_addr, text, sizeof text);
  }
  return text;
}

ssize_t read_stream(void* cls, uint64_t, char* out, size_t max) {
  auto& s = **static_cast<std::shared_ptr<Stream>*>(cls);
  std::lock_guard<std::mutex> lock(s.m);
  if (!s.buffer.empty()) {
    const std::size_t n = std::min(max, s.buffer.size());
    std::memcpy(out, s.buffer.data(), n);
    s.buffer.erase(0, n);
    s.cv.notify_all();
    return static_cast<ssize_t>(n);
  }
  if (s.done) return MHD_CONTENT_READER_END_OF_STREAM;
  s.suspended = true;
  MHD_suspend_connection(s.connection);
  return 0;
}

void free_stream(void* cls) {
  auto* holder = static_cast<std::shared_ptr<Stream>*>(cls);
  {
    std::lock_guard<std::mutex> lock((*holder)->m);
    (*holder)->closed = true;
    (*holder)->cv.notify_all();
  }
  delete holder;
}

void resume_if_suspended(Stream& s) {  // with s.m held
  if (s.suspended && !s.closed) {
    s.suspended = false;
    MHD_resume_connection(s.connection);
  }
}

}  // namespace

std::string HttpRequest::get_header_value(const std::string& name) const {
  const auto it = headers.find(lower(name));
  return it == headers.end() ? std::string() : it->second;
}

std::string HttpRequest::get_param_value(const std::string& name) const {
  const auto it = params.find(name);
  return it == params.end() ? std::string() : it->second;
}

void HttpResponse::set_content(std::string content, const std::string& content_type) {
  body = std::move(content);
  set_header("Content-Type", content_type);
}

void HttpResponse::set_chunked_content_provider(const std::string& content_type, StreamProvider provider,
                                                std::function<void()> done) {
  set_header("Content-Type", content_type);
  stream = std::move(provider);
  on_done = std::move(done);
}

struct HttpServer::Impl {
  HttpServer& owner;
  ServerTls tls;
  MHD_Daemon* daemon = nullptr;
  std::mutex m;
  std::condition_variable cv;
  std::deque<std::function<void()>> jobs;
  std::vector<std::thread> workers;
  bool stopping = false;

  // The request deadline: per connection, its socket and since when a request is being received. A connection
  // leaves the map (under clocks_m) before libmicrohttpd closes its socket, so a shutdown never hits a reused fd.
  struct Clock {
    int fd = -1;
    std::chrono::steady_clock::time_point since;
    bool receiving = true;
  };
  std::mutex clocks_m;
  std::condition_variable clocks_cv;
  std::unordered_map<MHD_Connection*, Clock> clocks;
  std::thread reaper;

  void clock(MHD_Connection* c, bool receiving) {
    std::lock_guard<std::mutex> lock(clocks_m);
    const auto it = clocks.find(c);
    if (it == clocks.end()) return;
    it->second.receiving = receiving;
    it->second.since = std::chrono::steady_clock::now();
  }

  void reap() {
    std::unique_lock<std::mutex> lock(clocks_m);
    for (;;) {
      clocks_cv.wait_for(lock, std::chrono::seconds(1));
      {
        std::lock_guard<std::mutex> stop_lock(m);
        if (stopping) return;
      }
      const auto limit = std::chrono::steady_clock::now() - std::chrono::seconds(kRequestDeadlineS);
      for (auto& [c, k] : clocks) {
        if (!k.receiving || k.since > limit) continue;
        k.receiving = false;
        shutdown(k.fd, SHUT_RDWR);  // the polling thread sees the end and closes the connection
        if (owner.on_refusal_) {
          owner.on_refusal_("request_deadline", "no complete request within " + std::to_string(kRequestDeadlineS) + " s");
        }
      }
    }
  }

  Impl(HttpServer& o, ServerTls t) : owner(o), tls(std::move(t)) {}

  void work() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock<std::mutex> lock(m);
        cv.wait(lock, [this] { return stopping || !jobs.empty(); });
        if (jobs.empty()) return;
        job = std::move(jobs.front());
        jobs.pop_front();
      }
      job();
    }
  }

  MHD_Result queue(MHD_Connection* connection, HttpResponse& res) {
    clock(connection, false);
    MHD_Response* r = nullptr;
    if (res.stream) {
      auto stream = std::make_shared<Stream>();
      stream->connection = connection;
      r = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 16 * 1024, read_stream,
                                            new std::shared_ptr<Stream>(stream), free_stream);
      auto provider = std::move(res.stream);
      auto done = std::move(res.on_done);
      post([stream, provider, done] { write_stream(*stream, provider, done); });
    } else {
      r = MHD_create_response_from_buffer(res.body.size(), res.body.data(), MHD_RESPMEM_MUST_COPY);
    }
    if (!r) return MHD_NO;
    for (const auto& [k, v] : owner.default_headers_) MHD_add_response_header(r, k.c_str(), v.c_str());
    for (const auto& [k, v] : res.headers) MHD_add_response_header(r, k.c_str(), v.c_str());
    const MHD_Result ok = MHD_queue_response(connection, static_cast<unsigned>(res.status), r);
    MHD_destroy_response(r);
    return ok;
  }

  // Refusals made here (not by a handler): a short JSON body like the service's own refusals.
  MHD_Result refuse(MHD_Connection* connection, int status, const std::string& error) {
    HttpResponse res;
    res.status = status;
    res.set_header("Cache-Control", "no-store");
    res.set_content("{\"answered\":false,\"error\":\"" + error + "\"}", "application/json");
    return queue(connection, res);
  }

  void post(std::function<void()> job) {
    std::lock_guard<std::mutex> lock(m);
    jobs.push_back(std::move(job));
    cv.notify_one();
  }

  static void write_stream(Stream& s, const StreamProvider& provider, const std::function<void()>& done) {
    const StreamSink sink = [&s](const std::string& chunk) {
      std::unique_lock<std::mutex> lock(s.m);
      s.cv.wait_for(lock, std::chrono::seconds(30), [&s] { return s.closed || s.buffer.size() < kMaxStreamBuffer; });
      if (s.closed || s.buffer.size() >= kMaxStreamBuffer) return false;
      s.buffer += chunk;
      resume_if_suspended(s);
      return true;
    };
    while (provider(sink)) {
      std::lock_guard<std::mutex> lock(s.m);
      if (s.closed) break;
    }
    {
      std::lock_guard<std::mutex> lock(s.m);
      s.done = true;
      resume_if_suspended(s);
    }
    if (done) done();
  }

  MHD_Result start_request(MHD_Connection* connection, const char* url, const char* method, void** con_cls);
  MHD_Result on_request(MHD_Connection* connection, const char* url, const char* method, const char* upload,
                        size_t* upload_size, void** con_cls);
};

MHD_Result HttpServer::Impl::start_request(MHD_Connection* connection, const char* url, const char* method,
                                           void** con_cls) {
  // The header count is bounded here; their bytes already were, by the connection's memory pool.
  if (MHD_get_connection_values(connection, MHD_HEADER_KIND, nullptr, nullptr) > static_cast<int>(kMaxHeaders)) {
    if (owner.on_refusal_) owner.on_refusal_("too_many_headers", "more than " + std::to_string(kMaxHeaders));
    return refuse(connection, 431, "too_many_headers: more than " + std::to_string(kMaxHeaders));
  }
  auto ex = std::make_shared<Exchange>();
  HttpRequest& req = ex->request;
  req.method = method;
  req.path = url;
  req.remote_addr = client_address(connection);
  MHD_get_connection_values(connection, MHD_HEADER_KIND, collect_header, &req.headers);
  const int arguments = MHD_get_connection_values(connection, MHD_GET_ARGUMENT_KIND, collect_param, &req.params);
  if (const std::string problem = query_problem(req.params, static_cast<std::size_t>(std::max(arguments, 0)));
      !problem.empty()) {
    if (owner.on_refusal_) owner.on_refusal_("bad_query", problem);
    return refuse(connection, 400, "bad_query: " + problem);
  }
  {
    std::lock_guard<std::mutex> lock(m);
    if (stopping) return refuse(connection, 503, "the server is stopping");
  }
  if (owner.pre_routing_ && owner.pre_routing_(req, ex->response)) return queue(connection, ex->response);
  ex->handler = owner.route(req);
  if (!ex->handler) return refuse(connection, 404, "not found");
  *con_cls = new std::shared_ptr<Exchange>(ex);
  return MHD_YES;
}

MHD_Result HttpServer::Impl::on_request(MHD_Connection* connection, const char* url, const char* method,
                                        const char* upload, size_t* upload_size, void** con_cls) {
  if (*con_cls == nullptr) return start_request(connection, url, method, con_cls);
  const std::shared_ptr<Exchange> ex = *static_cast<std::shared_ptr<Exchange>*>(*con_cls);
  if (*upload_size > 0) {  // a part of the body: kept while within the bound, read and dropped beyond it
    if (ex->request.body.size() + *upload_size > kMaxBodyBytes) {
      ex->too_large = true;
    } else if (!ex->too_large) {
      ex->request.body.append(upload, *upload_size);
    }
    *upload_size = 0;
    return MHD_YES;
  }
  clock(connection, false);  // the request is in
  if (ex->too_large) {
    if (owner.on_refusal_) owner.on_refusal_("body_too_large", "chunked body over " + std::to_string(kMaxBodyBytes));
    return refuse(connection, 413, "body_too_large: more than " + std::to_string(kMaxBodyBytes) + " bytes");
  }
  if (!ex->dispatched) {  // the handler may wait: it runs on a worker while the connection is suspended
    ex->dispatched = true;
    MHD_suspend_connection(connection);
    post([this, ex, connection] {
      try {
        (*ex->handler)(ex->request, ex->response);
      } catch (const std::exception& e) {  // a handler's failure is this request's, never the process's
        if (owner.on_refusal_) owner.on_refusal_("handler_error", e.what());
        ex->response = HttpResponse{};
        ex->response.status = 500;
        ex->response.set_content("{\"answered\":false,\"error\":\"internal error\"}", "application/json");
      }
      ex->ready.store(true);
      MHD_resume_connection(connection);
    });
    return MHD_YES;
  }
  if (!ex->ready.load()) return MHD_YES;
  return queue(connection, ex->response);
}

namespace {

MHD_Result access_handler(void* cls, MHD_Connection* connection, const char* url, const char* method,
                          const char*, const char* upload, size_t* upload_size, void** con_cls) {
  return static_cast<HttpServer::Impl*>(cls)->on_request(connection, url, method, upload, upload_size, con_cls);
}

void request_completed(void* cls, MHD_Connection* connection, void** con_cls, MHD_RequestTerminationCode) {
  delete static_cast<std::shared_ptr<Exchange>*>(*con_cls);
  *con_cls = nullptr;
  static_cast<HttpServer::Impl*>(cls)->clock(connection, true);  // the next request's deadline starts now
}

void connection_changed(void* cls, MHD_Connection* connection, void**, MHD_ConnectionNotificationCode code) {
  auto& impl = *static_cast<HttpServer::Impl*>(cls);
  std::lock_guard<std::mutex> lock(impl.clocks_m);
  if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
    impl.clocks.erase(connection);
    return;
  }
  const MHD_ConnectionInfo* info = MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CONNECTION_FD);
  if (info) impl.clocks[connection] = {info->connect_fd, std::chrono::steady_clock::now(), true};
}

}  // namespace

HttpServer::HttpServer(ServerTls tls, std::size_t workers) : impl_(std::make_unique<Impl>(*this, std::move(tls))) {
  for (std::size_t i = 0; i < workers; ++i) impl_->workers.emplace_back([this] { impl_->work(); });
}

HttpServer::~HttpServer() { stop(); }

namespace {

bool is_pattern(const std::string& path) { return path.find_first_of("()[]*+?\\|{}^$") != std::string::npos; }

}  // namespace

void HttpServer::Get(const std::string& path, HttpHandler handler) {
  HttpHandler& slot = get_routes_[path] = std::move(handler);
  if (is_pattern(path)) get_patterns_.emplace_back(std::regex(path), &slot);
}

void HttpServer::Post(const std::string& path, HttpHandler handler) {
  HttpHandler& slot = post_routes_[path] = std::move(handler);
  if (is_pattern(path)) post_patterns_.emplace_back(std::regex(path), &slot);
}

const HttpHandler* HttpServer::route(HttpRequest& req) const {
  const bool get = req.method == "GET" || req.method == "HEAD";
  if (!get && req.method != "POST") return nullptr;
  const auto& exact = get ? get_routes_ : post_routes_;
  if (const auto it = exact.find(req.path); it != exact.end() && !is_pattern(req.path)) return &it->second;
  std::smatch m;
  for (const auto& [pattern, handler] : get ? get_patterns_ : post_patterns_) {
    if (std::regex_match(req.path, m, pattern)) {
      for (const auto& part : m) req.matches.push_back(part.str());
      return handler;
    }
  }
  return nullptr;
}

int HttpServer::listen(const std::string& address, int port) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(address.c_str(), nullptr, &hints, &found) != 0 || !found) return 0;
  sockaddr_storage where{};
  std::memcpy(&where, found->ai_addr, found->ai_addrlen);
  const bool v6 = found->ai_family == AF_INET6;
  freeaddrinfo(found);
  if (v6) {
    reinterpret_cast<sockaddr_in6*>(&where)->sin6_port = htons(static_cast<std::uint16_t>(port));
  } else {
    reinterpret_cast<sockaddr_in*>(&where)->sin_port = htons(static_cast<std::uint16_t>(port));
  }
  unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_AUTO | MHD_ALLOW_SUSPEND_RESUME;
  if (v6) flags |= MHD_USE_IPv6;
  const bool tls = !impl_->tls.cert_pem.empty();
  if (tls) flags |= MHD_USE_TLS;
  impl_->daemon = MHD_start_daemon(
      flags, 0, nullptr, nullptr, access_handler, impl_.get(), MHD_OPTION_SOCK_ADDR, &where,
      MHD_OPTION_CONNECTION_MEMORY_LIMIT, static_cast<size_t>(kConnectionMemoryBytes), MHD_OPTION_CONNECTION_LIMIT,
      kMaxConnections, MHD_OPTION_PER_IP_CONNECTION_LIMIT, kMaxConnectionsPerAddress, MHD_OPTION_CONNECTION_TIMEOUT,
      kIdleTimeoutS, MHD_OPTION_NOTIFY_COMPLETED, request_completed, impl_.get(),
      MHD_OPTION_NOTIFY_CONNECTION, connection_changed, impl_.get(), MHD_OPTION_HTTPS_MEM_CERT,
      tls ? impl_->tls.cert_pem.c_str() : nullptr, MHD_OPTION_HTTPS_MEM_KEY, tls ? impl_->tls.key_pem.c_str() : nullptr,
      MHD_OPTION_END);
  if (!impl_->daemon) return 0;
  impl_->reaper = std::thread([this] { impl_->reap(); });
  const MHD_DaemonInfo* info = MHD_get_daemon_info(impl_->daemon, MHD_DAEMON_INFO_BIND_PORT);
  return info ? info->port : port;
}

void HttpServer::stop() {
  if (!impl_) return;
  {
    std::lock_guard<std::mutex> lock(impl_->m);
    impl_->stopping = true;
    impl_->cv.notify_all();
  }
  // The workers finish what they run (handlers see the caller's stop flag); every suspended connection is
  // resumed by then, which MHD requires before it stops.
  for (auto& w : impl_->workers) {
    if (w.joinable()) w.join();
  }
  impl_->clocks_cv.notify_all();
  if (impl_->reaper.joinable()) impl_->reaper.join();
  if (impl_->daemon) {
    MHD_stop_daemon(impl_->daemon);
    impl_->daemon = nullptr;
  }
}

}  // namespace causal::http
