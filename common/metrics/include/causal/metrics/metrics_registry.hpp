// Prometheus metrics of one process: counters, gauges and histograms kept by prometheus-cpp (Debian's
// prometheus-cpp-dev, "core"), rendered by its text serializer (exposition format 0.0.4) for a /metrics
// endpoint. This layer adds what the services rely on: one name prefix (kMetricPrefix), names checked against
// the conventions (`_total` on counters, base units), a name never reused with another type, gauges and
// counters read at scrape time from their owner (callbacks, gone with their handle), and, for the process's
// own registry, build_info and the standard process_* metrics.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace prometheus {
class Collectable;
class Counter;
class Gauge;
class Histogram;
class Registry;
}  // namespace prometheus

namespace causal::metrics {

inline constexpr const char* kMetricPrefix = "causal_twin_";

// Label name -> value, e.g. {{"topic", "causal_twin/alarm"}}. Ordered, so one label set renders one way.
using Labels = std::map<std::string, std::string>;

// Handles to prometheus-cpp metrics (owned by the registry, alive as long as it is); updates are lock-free.
class Counter {
 public:
  explicit Counter(prometheus::Counter& c) : c_(&c) {}
  void inc(double by = 1.0);  // by >= 0 (a negative or non-finite increment is ignored: counters only go up)
  double value() const;

 private:
  prometheus::Counter* c_;
};

class Gauge {
 public:
  explicit Gauge(prometheus::Gauge& g) : g_(&g) {}
  void set(double v);
  void add(double by);  // non-finite: ignored
  double value() const;

 private:
  prometheus::Gauge* g_;
};

class Histogram {
 public:
  explicit Histogram(prometheus::Histogram& h) : h_(&h) {}
  void observe(double v);  // non-finite values are ignored

 private:
  prometheus::Histogram* h_;
};

// Latency buckets in seconds from 50 us to 10 s (1-2.5-5 steps): processing one snapshot or frame.
std::vector<double> latency_buckets_seconds();

// A gauge whose value is read at scrape time (queue depths, matched readers): registered by its owner and
// removed when the returned handle is destroyed, so a scrape never calls into an object that is gone. The
// reader runs under the registry's lock: it must only read (atomics, DDS status calls), never take a lock of
// its owner or touch the registry.
class CallbackHandle {
 public:
  CallbackHandle() = default;
  CallbackHandle(std::function<void()> unregister) : unregister_(std::move(unregister)) {}
  CallbackHandle(CallbackHandle&& other) noexcept : unregister_(std::move(other.unregister_)) { other.unregister_ = nullptr; }
  CallbackHandle& operator=(CallbackHandle&& other) noexcept;
  CallbackHandle(const CallbackHandle&) = delete;
  CallbackHandle& operator=(const CallbackHandle&) = delete;
  ~CallbackHandle() { reset(); }
  void reset();

 private:
  std::function<void()> unregister_;
};

class MetricsRegistry {
 public:
  // with_process_metrics: also build_info (version) and process_* (CPU, memory, file descriptors, start time).
  explicit MetricsRegistry(bool with_process_metrics = false);
  ~MetricsRegistry();
  MetricsRegistry(const MetricsRegistry&) = delete;
  MetricsRegistry& operator=(const MetricsRegistry&) = delete;

  // The metric `name` (without the prefix) with these labels, created at the first call; the same object
  // afterwards. Throws std::invalid_argument for an invalid name or label, or a name reused with another type.
  Counter& counter(const std::string& name, const std::string& help, const Labels& labels = {});
  Gauge& gauge(const std::string& name, const std::string& help, const Labels& labels = {});
  Histogram& histogram(const std::string& name, const std::string& help, const Labels& labels,
                       const std::vector<double>& upper_bounds);
  [[nodiscard]] CallbackHandle gauge_callback(const std::string& name, const std::string& help, const Labels& labels,
                                              std::function<double()> read);
  // A counter whose cumulative value lives elsewhere (e.g. a DDS status such as samples lost).
  [[nodiscard]] CallbackHandle counter_callback(const std::string& name, const std::string& help, const Labels& labels,
                                                std::function<double()> read);

  // Every family in name order, each with its # HELP and # TYPE lines, then its samples (prometheus-cpp's
  // TextSerializer).
  std::string exposition() const;

 private:
  enum class Type { Counter, Gauge, Histogram };
  struct Family {
    Type type;
    std::string help;
    void* prometheus_family = nullptr;  // prometheus::Family<Counter|Gauge|Histogram>, by type
    std::map<Labels, std::unique_ptr<Counter>> counters;
    std::map<Labels, std::unique_ptr<Gauge>> gauges;
    std::map<Labels, std::unique_ptr<Histogram>> histograms;
    std::map<Labels, std::pair<std::uint64_t, std::function<double()>>> callbacks;  // id, reader
  };
  class Scrape;  // the prometheus::Collectable view: registry + callbacks (+ process metrics), merged by name
  friend class Scrape;
  Family& family(const std::string& name, Type type, const std::string& help, const Labels& labels);
  CallbackHandle add_callback(const std::string& name, Type type, const std::string& help, const Labels& labels,
                              std::function<double()> read);

  mutable std::mutex mutex_;
  std::shared_ptr<prometheus::Registry> registry_;
  std::map<std::string, Family> families_;
  std::uint64_t next_callback_id_ = 1;
  bool with_process_metrics_;
};

// The process's registry (like prometheus-cpp's default registry): services and the DDS endpoints count
// into it; the /metrics endpoint renders it. It has build_info and the process_* metrics.
MetricsRegistry& process_metrics();

}  // namespace causal::metrics
