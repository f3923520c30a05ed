// The /metrics endpoint of a service: the product's HTTP server (causal/http/http_server.hpp, libmicrohttpd) on
// its own polling thread, bound to 127.0.0.1 by default, serving process_metrics() in the Prometheus text format.
// Its limits are twin-web's: a slow, idle or greedy client cannot starve a scrape or grow the process.
#pragma once

#include "causal/metrics/metrics_registry.hpp"

#include <memory>
#include <string>

namespace causal::metrics {

class MetricsServer {
 public:
  // Binds at once and throws std::runtime_error naming the address when it cannot (port in use, bad address),
  // so a service asked for metrics never runs without them. port 0 = no server (url() is empty).
  MetricsServer(MetricsRegistry& registry, const std::string& bind_address, int port);
  ~MetricsServer();
  MetricsServer(const MetricsServer&) = delete;
  MetricsServer& operator=(const MetricsServer&) = delete;

  // http://ADDRESS:PORT/metrics, or "" when disabled.
  std::string url() const { return url_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string url_;
};

}  // namespace causal::metrics
