#include "causal/metrics/metrics_server.hpp"

#include <httplib.h>

#include <sys/socket.h>

#include <chrono>
#include <stdexcept>
#include <thread>

namespace causal::metrics {

struct MetricsServer::Impl {
  httplib::Server server;
  std::thread thread;
};

MetricsServer::MetricsServer(MetricsRegistry& registry, const std::string& bind_address, int port) {
  if (port == 0) return;
  if (port < 0 || port > 65535) throw std::runtime_error("metrics port " + std::to_string(port) + " is not a TCP port");
  impl_ = std::make_unique<Impl>();
  impl_->server.Get("/metrics", [&registry](const httplib::Request&, httplib::Response& res) {
    res.set_content(registry.exposition(), "text/plain; version=0.0.4; charset=utf-8");
  });
  impl_->server.Get("/", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("metrics at /metrics\n", "text/plain");
  });
  // httplib's default also sets SO_REUSEPORT, which lets a second service bind the same port and share its
  // scrapes unnoticed; SO_REUSEADDR alone still allows a restart while old connections are in TIME_WAIT.
  impl_->server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  if (!impl_->server.bind_to_port(bind_address.c_str(), port)) {
    throw std::runtime_error("cannot serve metrics on " + bind_address + ":" + std::to_string(port) +
                             " (port in use or address not local)");
  }
  impl_->thread = std::thread([this] { impl_->server.listen_after_bind(); });
  // stop() before the listen loop runs would be lost and the destructor's join would wait for ever.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!impl_->server.is_running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!impl_->server.is_running()) {
    impl_->server.stop();
    impl_->thread.detach();  // never started: nothing of ours runs on it
    impl_.reset();
    throw std::runtime_error("metrics server on " + bind_address + ":" + std::to_string(port) + " did not start");
  }
  url_ = "http://" + bind_address + ":" + std::to_string(port) + "/metrics";
}

MetricsServer::~MetricsServer() {
  if (!impl_) return;
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

}  // namespace causal::metrics
