#include "causal/dds/service_runtime.hpp"

#include <fastdds/dds/log/Log.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdlib>
#include <pthread.h>
#include <stdexcept>

namespace causal::dds {

std::string default_dds_dir() {
  if (const char* env = std::getenv("CAUSAL_TWIN_DDS_DIR"); env != nullptr && *env != '\0') return env;
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds";
}

void add_common_options(CLI::App& app, CommonOptions& options) {
  const std::string dir = default_dds_dir();
  if (options.qos_file.empty()) options.qos_file = dir + "/qos.xml";
  if (options.transport_file.empty()) options.transport_file = dir + "/localhost.xml";
  app.add_option("--domain", options.domain_id, "DDS domain id (0..232); use a private one per plant cell or test")
      ->check(CLI::Range(0, 232))
      ->envname("CAUSAL_TWIN_DOMAIN_ID")
      ->capture_default_str();
  app.add_option("--dds-qos", options.qos_file, "XML file with the topics' QoS profiles")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  app.add_option("--dds-transport", options.transport_file,
                 "XML file with the participant/transport profile (loopback by default; deploy/dds/plant.xml "
                 "is the template for a plant network)")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  app.add_option("--log-level", options.log_level, "trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
  app.add_option("--metrics-port", options.metrics_port,
                 "serve Prometheus metrics at http://<metrics-bind>:PORT/metrics (0 = off)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--metrics-bind", options.metrics_bind, "address the metrics endpoint listens on")
      ->capture_default_str();
  app.set_version_flag("--version", std::string(CAUSAL_TWIN_VERSION));
}

DdsSettings to_dds_settings(const CommonOptions& options, const std::string& participant_name) {
  DdsSettings s;
  s.profile_files = {options.qos_file, options.transport_file};
  s.domain_id = options.domain_id;
  s.participant_name = participant_name;
  return s;
}

void setup_logging(const std::string& service_name, const std::string& level) {
  auto logger = spdlog::stdout_color_mt(service_name);
  spdlog::set_default_logger(logger);
  const auto lvl = spdlog::level::from_str(level);
  if (lvl == spdlog::level::off && level != "off") throw std::invalid_argument("unknown log level " + level);
  spdlog::set_level(lvl);
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e [%n] %^%l%$ %v");
  spdlog::flush_on(spdlog::level::info);
  // Fast DDS logs its own errors to stderr; at debug level and below, show its warnings too.
  using eprosima::fastdds::dds::Log;
  Log::SetVerbosity(lvl <= spdlog::level::debug ? Log::Kind::Warning : Log::Kind::Error);
}

namespace {
sigset_t shutdown_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGUSR2);  // internal: wakes the signal thread when the process ends normally
  return set;
}
}  // namespace

ShutdownSignal::ShutdownSignal() {
  const sigset_t set = shutdown_set();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

void ShutdownSignal::start(std::function<void(int)> on_signal) {
  thread_ = std::thread([on_signal = std::move(on_signal)]() {
    const sigset_t set = shutdown_set();
    int sig = 0;
    if (sigwait(&set, &sig) == 0 && sig != SIGUSR2) on_signal(sig);
  });
}

ShutdownSignal::~ShutdownSignal() {
  if (thread_.joinable()) {
    pthread_kill(thread_.native_handle(), SIGUSR2);
    thread_.join();
  }
}

}  // namespace causal::dds
