// twin-web's HTTP side (http_server.hpp: libmicrohttpd, a worker pool): the embedded page, Chart.js from Debian's
// libjs-chart.js, the state as JSON (/api/state), the same state pushed as Server-Sent Events (/api/events) and
// what-if questions (POST /api/whatif). It only reads TwinState's serialised copy and talks to the DDS thread
// through WhatIfBridge: no DDS call happens on a web thread.
#pragma once

#include "alarm_action_bridge.hpp"
#include "approval_request.hpp"
#include "history_routes.hpp"
#include "http_server.hpp"
#include "twin_state.hpp"
#include "web_guard.hpp"
#include "whatif_bridge.hpp"

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace causal::web {

struct WebOptions {
  std::string bind = "127.0.0.1";
  int port = 8080;  // 0: any free port (logged)
  std::string chartjs = "/usr/share/javascript/chart.js/chart.min.js";
  double whatif_timeout_s = 10.0;
  int max_event_streams = 8;  // open pages at once (each holds one worker); more get polling
  // Hardening (web_guard.hpp): extra Host names, HTTPS (both files or neither), basic authentication.
  std::vector<std::string> allowed_hosts;
  std::string tls_cert;
  std::string tls_key;
  std::string basic_auth_file;  // one line USER:PASSWORD, mode 0600; "" = no authentication
  // The approve button: an approval starts this many snapshots after the plant's latest one (causal-approve --lead).
  std::uint64_t approval_lead = 3;
  // ... and holds the change for this many snapshots (causal-approve --duration); 0: the recommendation's horizon,
  // at least 12. A duration in the request wins.
  std::uint64_t approval_duration = 0;
};

class WebServer {
 public:
  // Binds the socket (throws std::runtime_error when it cannot). `whatif_readers` says how many what-if
  // readers (alarm-recommenders) the DDS side sees, for a truthful "no reply" message.
  WebServer(WebOptions options, TwinState& state, WhatIfBridge& whatif, std::function<std::size_t()> whatif_readers);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // /api/history answers from these routes (twin-web --db); without, it answers 404. Before start().
  void set_history(HistoryRoutes* history) { history_ = history; }
  // POST /api/alarm_action sends through this bridge (alarm_action_route.cpp); without, it answers 503. Before start().
  void set_alarm_actions(AlarmActionBridge* actions) { actions_ = actions; }
  // POST /api/approve plans with this clock and sends through this bridge (approve_route.cpp); without, it
  // answers 503. Before start().
  void set_approvals(ApprovalBridge* approvals, const SourceClock* clock) {
    approvals_ = approvals;
    clock_ = clock;
  }
  void start();  // serves on its own thread
  void stop();   // closes the socket and every event stream; joins the thread
  int port() const { return port_; }
  const std::string& bind_address() const { return options_.bind; }
  const char* scheme() const { return options_.tls_cert.empty() ? "http" : "https"; }

 private:
  void routes();
  void history_route();  // GET /api/history (twin-web --db)
  void guard_requests();
  void alarm_action_route();  // POST /api/alarm_action
  void approve_route();       // POST /api/approve

  WebOptions options_;
  TwinState& state_;
  WhatIfBridge& whatif_;
  std::function<std::size_t()> whatif_readers_;
  std::unique_ptr<RequestGuard> guard_;
  HistoryRoutes* history_ = nullptr;
  AlarmActionBridge* actions_ = nullptr;
  ApprovalBridge* approvals_ = nullptr;
  const SourceClock* clock_ = nullptr;
  std::unique_ptr<HttpServer> server_;
  std::string chartjs_;  // read once at start-up from the package path
  int port_ = 0;
  std::atomic<bool> stopping_{false};
  std::atomic<int> event_streams_{0};
  std::atomic<std::uint64_t> next_request_{0};
};

}  // namespace causal::web
