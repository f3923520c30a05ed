#include "causal/metrics/metrics_server.hpp"

#include "causal/http/http_server.hpp"

#include <stdexcept>

namespace causal::metrics {

namespace {

// A scrape is answered at once (the exposition is rendered in memory), so two workers serve a Prometheus and a
// person with curl; slow or idle clients are bounded by the server (http_server.hpp), not by the workers.
constexpr std::size_t kWorkers = 2;

}  // namespace

struct MetricsServer::Impl {
  http::HttpServer server{{}, kWorkers};
};

MetricsServer::MetricsServer(MetricsRegistry& registry, const std::string& bind_address, int port) {
  if (port == 0) return;
  if (port < 0 || port > 65535) throw std::runtime_error("metrics port " + std::to_string(port) + " is not a TCP port");
  impl_ = std::make_unique<Impl>();
  impl_->server.Get("/metrics", [&registry](const http::HttpRequest&, http::HttpResponse& res) {
    res.set_content(registry.exposition(), "text/plain; version=0.0.4; charset=utf-8");
  });
  impl_->server.Get("/", [](const http::HttpRequest&, http::HttpResponse& res) {
    res.set_content("metrics at /metrics\n", "text/plain");
  });
  // Refusals the server makes itself (a client over the header count, past the request deadline) are counted
  // in the registry it serves.
  const char* help = "Requests to the /metrics endpoint refused by its server, by reason";
  impl_->server.set_refusal_observer([&registry, help](const std::string& reason, const std::string&) {
    registry.counter("metrics_requests_refused_total", help, {{"reason", reason}}).inc();
  });
  // libmicrohttpd binds without SO_REUSEPORT, so a second service cannot bind the same port and share its
  // scrapes unnoticed; a busy port or an address that is not local fails here.
  if (impl_->server.listen(bind_address, port) == 0) {
    impl_.reset();
    throw std::runtime_error("cannot serve metrics on " + bind_address + ":" + std::to_string(port) +
                             " (port in use or address not local)");
  }
  url_ = "http://" + bind_address + ":" + std::to_string(port) + "/metrics";
}

MetricsServer::~MetricsServer() {
  if (impl_) impl_->server.stop();
}

}  // namespace causal::metrics
