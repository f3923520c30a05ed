// What every service process shares: DDS command-line options, logging set-up and clean shutdown on
// SIGINT/SIGTERM. Signals are blocked in every thread and received by one sigwait() thread, which then
// calls the service's stop function from a normal thread context (no work inside a signal handler).
#pragma once

#include "causal/config/exit_codes.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/revocation_watch.hpp"
#include "causal/dds/systemd_notify.hpp"
#include "causal/metrics/metrics_server.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <chrono>
#include <cstdlib>
#include <thread>
#include <vector>

namespace causal::dds {

struct CommonOptions {
  int domain_id = 0;
  std::string qos_file;        // qos.xml from the configuration search (causal/config/config_search.hpp)
  std::string transport_file;  // localhost.xml from the same search
  bool qos_from_flag = false;        // --qos given on the command line
  bool transport_from_flag = false;  // --transport given on the command line
  std::string log_level = "info";
  std::string security_dir;       // --security DIR: PKI folder of deploy/security/make-pki.sh ("off" = open)
  std::string security_identity;  // --security-identity NAME: the identity folder in it (default: per service)
  int metrics_port = 0;                       // 0 = no /metrics endpoint
  std::string metrics_bind = "127.0.0.1";     // loopback unless the operator opens it on purpose
  double ack_stall_s = 7.0;  // --ack-stall: readers not acknowledging this long raise a HEALTH alarm (ack_watch.hpp);
                             // longer than the 5 s lease, so a crashed reader is reported by its lease alone
};

// Folder of the qos.xml the configuration search chose ("" when none): flag, $CAUSAL_TWIN_DDS_DIR, the source
// tree only for a build-tree binary, /etc/causal-twin, <prefix>/share/causal-twin/dds.
std::string default_dds_dir();

// Adds --domain, --qos (alias --dds-qos), --transport (alias --dds-transport), --log-level, --security,
// --security-identity, --metrics-port, --metrics-bind and --version (the project version) to a CLI11 app. The
// defaults of --qos and --transport come from the configuration search, and --help says which file was chosen.
void add_common_options(CLI::App& app, CommonOptions& options);

// The XML files a participant loads: qos_file, then transport_file; but when $FASTRTPS_DEFAULT_PROFILES_FILE
// is set (default_profiles_env, "" or null = unset) and neither --transport nor --qos was given, that file
// replaces transport_file, as in every Fast DDS application.
struct ProfileFiles {
  std::vector<std::string> files;
  bool from_environment = false;
};
ProfileFiles choose_profile_files(const CommonOptions& options, const char* default_profiles_env);

DdsSettings to_dds_settings(const CommonOptions& options, const std::string& participant_name);

// Console logger "<service>" with the given level ("trace".."off"); throws on an unknown level.
void setup_logging(const std::string& service_name, const std::string& level);

class ShutdownSignal {
 public:
  // Must be constructed before any thread (e.g. DDS) is created, so all threads inherit the blocked mask.
  ShutdownSignal();
  ~ShutdownSignal();
  ShutdownSignal(const ShutdownSignal&) = delete;
  ShutdownSignal& operator=(const ShutdownSignal&) = delete;

  // on_signal runs once, on the signal thread, when SIGINT or SIGTERM arrives.
  void start(std::function<void(int)> on_signal);

 private:
  std::thread thread_;
};

// The body of every service's main(): logging, the node built by make_node() (a std::unique_ptr to a type
// with run() and stop()), SIGINT/SIGTERM routed to stop(), and exit codes: run()'s own, 2 for invalid
// input or configuration (std::invalid_argument, e.g. causal::config::ConfigError), 1 for anything else.
// How long a service may take to tear down its DDS entities after run() returned (see run_service).
inline constexpr std::chrono::seconds kTeardownBound{5};

template <typename MakeNode>
int run_service(ShutdownSignal& signals, const std::string& name, const CommonOptions& options, MakeNode&& make_node) {
  try {
    setup_logging(name, options.log_level);
    // Before the node: a port that cannot be bound is a configuration error (exit 2), found before any DDS work.
    std::unique_ptr<metrics::MetricsServer> metrics_server;
    if (options.metrics_port != 0) {
      try {
        metrics_server = std::make_unique<metrics::MetricsServer>(metrics::process_metrics(), options.metrics_bind,
                                                                  options.metrics_port);
      } catch (const std::runtime_error& e) {
        throw std::invalid_argument(e.what());
      }
      spdlog::info("metrics: {} {}", name, metrics_server->url());
    }
    auto node = make_node();
    std::mutex node_mutex;  // the signal thread must not reach a node that is being torn down
    bool signalled = false;  // guarded by node_mutex: a stop asked for is never turned into a restart
    signals.start([&node, &node_mutex, &signalled](int sig) {
      std::lock_guard<std::mutex> lock(node_mutex);
      spdlog::info("signal {} received, stopping", sig);
      signalled = true;
      if (node) node->stop();
    });
    // A new revocation list restarts the process in place (revocation_watch.hpp): a clean stop first.
    std::atomic<bool> restart{false};
    bool running = true;  // guarded by node_mutex: a run that has ended is not restarted
    struct WatchStop {    // declared after what the watch's callback uses, so it is stopped before they go
      ~WatchStop() { process_revocation_watch().stop(); }
    } watch_stop;
    process_revocation_watch().start(kRevocationPoll, [&](const std::string& crl) {
      std::lock_guard<std::mutex> lock(node_mutex);
      if (!running || signalled) return;
      spdlog::warn("revocation list {} changed: stopping cleanly and restarting to load it (revoked peers are "
                   "refused from then on)", crl);
      restart = true;
      notify_systemd_reloading();
      if (node) node->stop();
    });
    const int code = node->run();
    {
      std::lock_guard<std::mutex> lock(node_mutex);
      running = false;
    }
    // Everything is delivered or counted by now. Tearing down the DDS entities can hang (measured: sensor-sim and
    // causal-estimator signalled together while 256 groups were in flight, each waiting on the other for
    // minutes), so it gets a bound: past it the process leaves with run()'s code. SIGTERM is always honoured.
    // A restart that cannot finish its teardown leaves with 1 instead, so a supervisor restarts it.
    std::thread([code = restart ? config::kExitFailed : code] {
      std::this_thread::sleep_for(kTeardownBound);
      spdlog::warn("DDS teardown did not finish within {} s: leaving now (exit code {})", kTeardownBound.count(), code);
      spdlog::default_logger()->flush();
      std::_Exit(code);
    }).detach();
    {
      std::lock_guard<std::mutex> lock(node_mutex);
      node.reset();
    }
    metrics_server.reset();
    process_revocation_watch().stop();
    bool exec_now = false;
    {
      std::lock_guard<std::mutex> lock(node_mutex);
      exec_now = restart && !signalled;
    }
    if (exec_now) {
      spdlog::warn("restarting with the new revocation list (this run's exit code was {})", code);
      exec_self();
      return config::kExitFailed;  // exec failed (logged): a supervisor restarts the unit (Restart=on-failure)
    }
    return code;
  } catch (const std::invalid_argument& e) {
    spdlog::critical("{}", e.what());
    return config::kExitUsage;
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return config::kExitFailed;
  }
}

// For tools without the common options (no metrics endpoint).
template <typename MakeNode>
int run_service(ShutdownSignal& signals, const std::string& name, const std::string& log_level, MakeNode&& make_node) {
  CommonOptions options;
  options.log_level = log_level;
  return run_service(signals, name, options, std::forward<MakeNode>(make_node));
}

}  // namespace causal::dds
