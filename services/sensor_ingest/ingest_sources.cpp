#include "ingest_sources.hpp"

#include <arpa/inet.h>
#include <mosquitto.h>
#include <netinet/in.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "causal/metrics/metrics_registry.hpp"

namespace causal::ingest {

bool MessageQueue::push(std::string message) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return closed_ || messages_.size() < capacity_; });
  if (closed_) return false;
  messages_.push_back(std::move(message));
  changed_.notify_all();
  return true;
}

std::optional<std::string> MessageQueue::pop(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, timeout, [this] { return closed_ || !messages_.empty(); });
  if (messages_.empty()) return std::nullopt;
  std::string m = std::move(messages_.front());
  messages_.pop_front();
  changed_.notify_all();
  return m;
}

void MessageQueue::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  changed_.notify_all();
}

bool MessageQueue::closed_and_empty() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_ && messages_.empty();
}

// ---- MQTT -------------------------------------------------------------------------------------------------

MqttSource::MqttSource(const IngestOptions& options, MessageQueue& queue)
    : spec_(options.source), qos_(options.mqtt_qos), queue_(queue) {
  static const int init = mosquitto_lib_init();  // once per process; the library stays up until exit
  (void)init;
  // Clean session by default: a restarted adapter starts with the broker's current traffic; QoS 1 covers the link.
  // --mqtt-keep-session: the broker keeps the subscription and queues what is published while the adapter is down
  // (a message handed to a process that then dies is still lost: libmosquitto 2.0 acknowledges before on_message).
  client_ = mosquitto_new(options.mqtt_client_id.c_str(), !options.mqtt_keep_session, this);
  if (!client_) throw std::runtime_error("mosquitto_new failed (out of memory or bad client id)");
  mosquitto_connect_callback_set(client_, &MqttSource::on_connect);
  mosquitto_disconnect_callback_set(client_, &MqttSource::on_disconnect);
  mosquitto_message_callback_set(client_, &MqttSource::on_message);
  secure(options.mqtt_security);
}

namespace {
std::string read_secret(const std::string& path, const char* option) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::invalid_argument(std::string(option) + " " + path + ": cannot read it");
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    throw std::invalid_argument(std::string(option) + " " + path + ": readable by others (chmod 600 it)");
  }
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  if (line.empty()) throw std::invalid_argument(std::string(option) + " " + path + ": the first line is empty");
  return line;
}
}  // namespace

void MqttSource::secure(const MqttSecurity& s) {
  if (!s.ca_file.empty()) {
    const char* cert = s.cert_file.empty() ? nullptr : s.cert_file.c_str();
    const char* key = s.key_file.empty() ? nullptr : s.key_file.c_str();
    const int rc = mosquitto_tls_set(client_, s.ca_file.c_str(), nullptr, cert, key, nullptr);
    if (rc != MOSQ_ERR_SUCCESS) {
      throw std::invalid_argument("--mqtt-cafile/--mqtt-cert/--mqtt-key: " + std::string(mosquitto_strerror(rc)));
    }
    // Verify the broker's certificate and its name (libmosquitto's default; said here so it stays so).
    mosquitto_tls_insecure_set(client_, false);
    mosquitto_tls_opts_set(client_, 1, "tlsv1.2", nullptr);
  }
  if (!s.username.empty()) {
    const std::string password = read_secret(s.password_file, "--mqtt-password-file");
    const int rc = mosquitto_username_pw_set(client_, s.username.c_str(), password.c_str());
    if (rc != MOSQ_ERR_SUCCESS) throw std::invalid_argument("--mqtt-username: " + std::string(mosquitto_strerror(rc)));
  }
  spdlog::info("mqtt: {}{}", s.ca_file.empty() ? "no TLS" : (s.cert_file.empty() ? "TLS" : "mutual TLS"),
               s.username.empty() ? ", no user name" : ", user " + s.username);
}

MqttSource::~MqttSource() {
  stop();
  mosquitto_destroy(client_);
}

void MqttSource::start() {
  thread_ = std::thread([this] { run(); });
}

void MqttSource::stop() {
  if (stopping_.exchange(true)) return;
  if (thread_.joinable()) thread_.join();
  mosquitto_disconnect(client_);
}

bool MqttSource::pause(std::chrono::milliseconds d) {
  const auto until = std::chrono::steady_clock::now() + d;
  while (!stopping_.load() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return !stopping_.load();
}

void MqttSource::run() {
  bool connected = false;
  std::uint64_t failures = 0;
  while (!stopping_.load()) {
    if (!connected) {
      const int rc = mosquitto_connect(client_, spec_.host.c_str(), spec_.port, 30);
      if (rc != MOSQ_ERR_SUCCESS) {
        // Not fatal: the broker may start after the adapter, or be restarting. Said once, then every minute.
        if (failures++ % 60 == 0) {
          spdlog::warn("mqtt: cannot connect to {}:{} ({}): retrying every second", spec_.host, spec_.port,
                       rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc));
        }
        pause(std::chrono::seconds(1));
        continue;
      }
      connected = true;
      failures = 0;
    }
    // Serves the socket (messages, acknowledgements, keep-alive) for up to 200 ms.
    if (mosquitto_loop(client_, 200, 1) != MOSQ_ERR_SUCCESS) {
      connected = false;
      pause(std::chrono::seconds(1));
    }
  }
}

void MqttSource::on_connect(struct mosquitto* m, void* self, int rc) {
  auto* s = static_cast<MqttSource*>(self);
  if (rc != 0) {
    spdlog::warn("mqtt: broker {}:{} refused the connection: {}", s->spec_.host, s->spec_.port,
                 mosquitto_connack_string(rc));
    return;
  }
  ++s->connects_;
  for (const auto& topic : s->spec_.topics) {
    const int sub = mosquitto_subscribe(m, nullptr, topic.c_str(), s->qos_);
    if (sub != MOSQ_ERR_SUCCESS) spdlog::error("mqtt: subscribe to '{}' failed: {}", topic, mosquitto_strerror(sub));
  }
  metrics::process_metrics().counter("ingest_mqtt_connects_total", "MQTT connections made (reconnects included)").inc();
  spdlog::info("mqtt: connected to {}:{} (connection {}), subscribed to {} with QoS {}", s->spec_.host, s->spec_.port,
               s->connects_, fmt::join(s->spec_.topics, ", "), s->qos_);
}

void MqttSource::on_disconnect(struct mosquitto*, void* self, int rc) {
  auto* s = static_cast<MqttSource*>(self);
  if (s->stopping_.load() || rc == 0) return;
  spdlog::warn("mqtt: lost the broker {}:{} ({}): reconnecting", s->spec_.host, s->spec_.port,
               rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc));
}

void MqttSource::on_message(struct mosquitto*, void* self, const struct mosquitto_message* msg) {
  auto* s = static_cast<MqttSource*>(self);
  if (s->stopping_.load()) return;
  s->queue_.push(std::string(static_cast<const char*>(msg->payload), static_cast<std::size_t>(msg->payloadlen)));
}

// ---- UDP and stdin ----------------------------------------------------------------------------------------

namespace {

class ThreadSource : public MessageSource {
 public:
  ~ThreadSource() override { stop(); }
  void stop() override {
    stopping_.store(true);
    if (thread_.joinable()) thread_.join();
  }

 protected:
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

// One datagram = one message (up to 65507 bytes, the IPv4 UDP maximum). Only datagrams from the allowed sender
// networks are taken (default loopback): UDP has no authentication, so a plant network's senders are listed.
class UdpSource : public ThreadSource {
 public:
  UdpSource(const SourceSpec& spec, std::vector<Ipv4Network> allow, MessageQueue& queue)
      : queue_(queue), allow_(std::move(allow)) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (fd_ < 0) throw std::runtime_error(std::string("udp socket: ") + std::strerror(errno));
    int size = 8 << 20;  // a large receive buffer rides out bursts while DDS is busy (the kernel caps it)
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(spec.port));
    if (::inet_pton(AF_INET, spec.host.c_str(), &addr.sin_addr) != 1) {
      ::close(fd_);
      throw std::invalid_argument("udp source '" + spec.text + "': the host must be an IPv4 address");
    }
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      const std::string why = std::strerror(errno);
      ::close(fd_);
      throw std::invalid_argument("udp source '" + spec.text + "': cannot bind: " + why);
    }
    std::string networks;
    for (const auto& n : allow_) {
      in_addr a{htonl(n.address)};
      char text[INET_ADDRSTRLEN] = {};
      ::inet_ntop(AF_INET, &a, text, sizeof text);
      networks += (networks.empty() ? "" : ", ") + std::string(text) + "/" + std::to_string(n.prefix);
    }
    spdlog::info("udp: listening on {}:{}, taking datagrams from {}", spec.host, spec.port, networks);
  }
  ~UdpSource() override {
    stop();
    ::close(fd_);
  }
  void start() override {
    thread_ = std::thread([this] {
      std::string buffer(65536, '\0');
      while (!stopping_.load()) {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, 200) <= 0) continue;
        sockaddr_in from{};
        socklen_t from_len = sizeof from;
        const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &from_len);
        if (n < 0) continue;
        if (!allowed(ntohl(from.sin_addr.s_addr))) {
          refuse(from);
          continue;
        }
        queue_.push(buffer.substr(0, static_cast<std::size_t>(n)));
      }
    });
  }

 private:
  bool allowed(std::uint32_t address) const {
    for (const auto& n : allow_) {
      if (n.contains(address)) return true;
    }
    return false;
  }
  void refuse(const sockaddr_in& from) {
    static auto& refused = metrics::process_metrics().counter(
        "ingest_udp_refused_total", "UDP datagrams refused: the sender is not in --udp-allow");
    refused.inc();
    ++refused_;
    if (refused_ == 1 || refused_ % 1000 == 0) {
      char text[INET_ADDRSTRLEN] = {};
      ::inet_ntop(AF_INET, &from.sin_addr, text, sizeof text);
      spdlog::warn("udp: refused a datagram from {}:{} (not in --udp-allow); {} refused so far", text,
                   ntohs(from.sin_port), refused_);
    }
  }

  MessageQueue& queue_;
  std::vector<Ipv4Network> allow_;
  std::uint64_t refused_ = 0;
  int fd_ = -1;
};

// A byte stream split into messages by BlockStreamSplitter; the queue is closed at end of input.
class StdinSource : public ThreadSource {
 public:
  StdinSource(const BlockLimits& limits, MessageQueue& queue) : queue_(queue), splitter_(limits) {}
  void start() override {
    thread_ = std::thread([this] {
      std::string chunk(1 << 16, '\0');
      bool eof = false;
      while (!stopping_.load() && !eof) {
        pollfd p{STDIN_FILENO, POLLIN, 0};
        if (::poll(&p, 1, 200) <= 0) continue;
        const ssize_t n = ::read(STDIN_FILENO, chunk.data(), chunk.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
          eof = true;
        } else {
          splitter_.append(chunk.data(), static_cast<std::size_t>(n));
        }
        while (auto m = splitter_.next(eof)) {
          if (!queue_.push(std::move(*m))) return;
        }
      }
      if (eof) {
        spdlog::info("stdin: end of input");
        queue_.close();
      }
    });
  }

 private:
  MessageQueue& queue_;
  BlockStreamSplitter splitter_;
};

}  // namespace

std::unique_ptr<MessageSource> make_source(const IngestOptions& options, MessageQueue& queue) {
  switch (options.source.kind) {
    case SourceKind::Mqtt:
      return std::make_unique<MqttSource>(options, queue);
    case SourceKind::Udp:
      return std::make_unique<UdpSource>(options.source, options.udp_allow, queue);
    case SourceKind::Stdin:
      return std::make_unique<StdinSource>(options.limits, queue);
  }
  throw std::invalid_argument("unknown source kind");
}

}  // namespace causal::ingest
