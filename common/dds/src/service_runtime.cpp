#include "causal/dds/service_runtime.hpp"

#include "causal/config/unit_environment.hpp"

#include <fastdds/dds/log/Log.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "causal/config/cli_conventions.hpp"
#include "causal/config/config_search.hpp"

#include <csignal>
#include <filesystem>
#include <cstdlib>
#include <pthread.h>
#include <stdexcept>

namespace causal::dds {

std::string default_dds_dir() {
  const config::ConfigChoice qos = config::find_config_file("qos.xml", "", config::ConfigKind::Dds);
  return qos.found() ? std::filesystem::path(qos.path).parent_path().string() : std::string();
}

void add_common_options(CLI::App& app, CommonOptions& options) {
  using config::ConfigKind;
  using config::find_config_file;
  const config::ConfigChoice qos = find_config_file("qos.xml", options.qos_file, ConfigKind::Dds);
  const config::ConfigChoice transport = find_config_file("localhost.xml", options.transport_file, ConfigKind::Dds);
  options.qos_file = qos.path;
  options.transport_file = transport.path;
  app.add_option("--domain", options.domain_id, "DDS domain id (0..232); use a private one per plant cell or test")
      ->check(CLI::Range(0, 232))
      ->envname("CAUSAL_TWIN_DOMAIN_ID")
      ->capture_default_str();
  app.add_option("--qos,--dds-qos", options.qos_file,
                 "XML file with the topics' QoS profiles; default: " + qos.describe("qos.xml"))
      ->check(CLI::ExistingFile)
      ->each([&options](const std::string&) { options.qos_from_flag = true; });
  app.add_option("--transport,--dds-transport", options.transport_file,
                 "XML file with the participant/transport profile (loopback by default; plant.xml is the template "
                 "for a plant network, discovery_client.xml for a discovery server); default: " +
                     transport.describe("localhost.xml") +
                     "; without --transport and --qos, $FASTRTPS_DEFAULT_PROFILES_FILE replaces it when set")
      ->check(CLI::ExistingFile)
      ->each([&options](const std::string&) { options.transport_from_flag = true; });
  app.add_option("--security", options.security_dir,
                 "DDS-Security: PKI folder made by deploy/security/make-pki.sh (authenticated, access-controlled, "
                 "encrypted bus; 'off' = open). Default: the transport profile's causal_twin.security_dir, else open")
      ->envname("CAUSAL_TWIN_SECURITY_DIR");
  app.add_option("--security-identity", options.security_identity,
                 "identity folder in the PKI (default: sensor, ingest (sensor-ingest), estimator, recommender, recorder or operator, by "
                 "service)");
  app.add_option("--log-level", options.log_level, "trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
  app.add_option("--metrics-port", options.metrics_port,
                 "serve Prometheus metrics at http://<metrics-bind>:PORT/metrics (0 = off)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--metrics-bind", options.metrics_bind, "address the metrics endpoint listens on")
      ->capture_default_str();
  app.add_option("--ack-stall", options.ack_stall_s,
                 "a reliable writer whose matched readers have not all acknowledged for this many seconds raises a "
                 "HEALTH alarm naming them (reader_not_acknowledging; 0 = off)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  config::add_version_flag(app);
  // Under systemd: a misspelt variable in an env file stops the service (exit 2) instead of being ignored.
  app.preparse_callback([](std::size_t) {
    if (const std::string problem = config::this_unit_environment_problem(); !problem.empty()) {
      throw CLI::ValidationError("environment", problem);
    }
  });
}

ProfileFiles choose_profile_files(const CommonOptions& options, const char* default_profiles_env) {
  ProfileFiles chosen;
  chosen.files.push_back(options.qos_file);
  const bool env_set = default_profiles_env != nullptr && *default_profiles_env != '\0';
  if (env_set && !options.transport_from_flag && !options.qos_from_flag) {
    // Like every Fast DDS application: the operator's default profiles file decides transport and discovery.
    chosen.files.emplace_back(default_profiles_env);
    chosen.from_environment = true;
  } else {
    chosen.files.push_back(options.transport_file);
  }
  return chosen;
}

DdsSettings to_dds_settings(const CommonOptions& options, const std::string& participant_name) {
  if (options.qos_file.empty()) {
    throw std::invalid_argument(config::find_config_file("qos.xml", "", config::ConfigKind::Dds).describe("qos.xml") +
                                ": give --qos FILE or set CAUSAL_TWIN_DDS_DIR");
  }
  const ProfileFiles chosen = choose_profile_files(options, std::getenv("FASTRTPS_DEFAULT_PROFILES_FILE"));
  if (!chosen.from_environment && options.transport_file.empty()) {
    throw std::invalid_argument(
        config::find_config_file("localhost.xml", "", config::ConfigKind::Dds).describe("localhost.xml") +
        ": give --transport FILE or set CAUSAL_TWIN_DDS_DIR");
  }
  DdsSettings s;
  s.profile_files = chosen.files;
  // A generic profiles file need not define our participant profile: its default participant profile is used.
  s.participant_profile_required = !chosen.from_environment;
  s.domain_id = options.domain_id;
  s.participant_name = participant_name;
  s.security_dir = options.security_dir;
  s.security_identity = options.security_identity;
  s.ack_stall_s = options.ack_stall_s;
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
