// Prometheus metrics of one process: counters, gauges and histograms, rendered in the Prometheus text
// exposition format (version 0.0.4) for a /metrics endpoint. Debian 12 has no prometheus-cpp package, and
// the format is small and stable (https://prometheus.io/docs/instrumenting/exposition_formats/), so this is
// written here: std only, lock-free updates (atomics), one mutex for registration and rendering.
//
// Names follow the Prometheus conventions: one prefix (kMetricPrefix), base units (seconds, bytes),
// `_total` on counters; a family (one name) has one type and one help text and many label sets.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace causal::metrics {

inline constexpr const char* kMetricPrefix = "causal_twin_";

// Label name -> value, e.g. {{"topic", "causal_twin/alarm"}}. Ordered, so one label set renders one way.
using Labels = std::map<std::string, std::string>;

class Counter {
 public:
  void inc(double by = 1.0);  // by >= 0 (a negative or non-finite increment is ignored: counters only go up)
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

class Gauge {
 public:
  void set(double v) { value_.store(v, std::memory_order_relaxed); }
  void add(double by);
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

class Histogram {
 public:
  explicit Histogram(std::vector<double> upper_bounds);  // strictly increasing, finite; +Inf is implicit
  void observe(double v);                                 // non-finite values are ignored
  const std::vector<double>& upper_bounds() const { return bounds_; }
  // Cumulative counts per bound (the last one is +Inf), the sum and the count, as one consistent-enough read.
  std::vector<std::uint64_t> cumulative_counts() const;
  double sum() const { return sum_.load(std::memory_order_relaxed); }

 private:
  std::vector<double> bounds_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> counts_;  // per bucket (not cumulative), bounds_.size() + 1
  std::atomic<double> sum_{0.0};
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

  // Every family in name order, each with its # HELP and # TYPE lines, then its samples.
  std::string exposition() const;

 private:
  enum class Type { Counter, Gauge, Histogram };
  struct Family {
    Type type;
    std::string help;
    std::map<Labels, std::unique_ptr<Counter>> counters;
    std::map<Labels, std::unique_ptr<Gauge>> gauges;
    std::map<Labels, std::unique_ptr<Histogram>> histograms;
    std::map<Labels, std::pair<std::uint64_t, std::function<double()>>> callbacks;  // id, reader
  };
  Family& family(const std::string& name, Type type, const std::string& help, const Labels& labels);
  CallbackHandle add_callback(const std::string& name, Type type, const std::string& help, const Labels& labels,
                              std::function<double()> read);

  mutable std::mutex mutex_;
  std::map<std::string, Family> families_;
  std::uint64_t next_callback_id_ = 1;
};

// The process's registry (like prometheus-cpp's default registry): services and the DDS endpoints count
// into it; the /metrics endpoint renders it.
MetricsRegistry& process_metrics();

// Escapes a label value for the exposition format: backslash, double quote and line feed.
std::string escape_label_value(const std::string& value);

}  // namespace causal::metrics
