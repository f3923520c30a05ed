#include "causal/metrics/metrics_registry.hpp"

#include "process_metrics.hpp"

#include <prometheus/collectable.h>
#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <stdexcept>

namespace causal::metrics {

namespace {

// [a-zA-Z_:][a-zA-Z0-9_:]* for metric names, [a-zA-Z_][a-zA-Z0-9_]* for label names (no "__" prefix).
bool valid_name(const std::string& name, bool label) {
  if (name.empty()) return false;
  if (label && name.rfind("__", 0) == 0) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || (!label && c == ':');
    const bool digit = c >= '0' && c <= '9';
    if (!(alpha || (i > 0 && digit))) return false;
  }
  return true;
}

prometheus::ClientMetric client_metric(const Labels& labels) {
  prometheus::ClientMetric m;
  for (const auto& [k, v] : labels) m.label.push_back({k, v});
  return m;
}

}  // namespace

void Counter::inc(double by) {
  if (!(by >= 0.0) || !std::isfinite(by)) return;
  c_->Increment(by);
}
double Counter::value() const { return c_->Value(); }

void Gauge::set(double v) { g_->Set(v); }
void Gauge::add(double by) {
  if (std::isfinite(by)) g_->Increment(by);
}
double Gauge::value() const { return g_->Value(); }

void Histogram::observe(double v) {
  if (std::isfinite(v)) h_->Observe(v);
}

std::vector<double> latency_buckets_seconds() {
  return {5e-5, 1e-4, 2.5e-4, 5e-4, 1e-3, 2.5e-3, 5e-3, 1e-2, 2.5e-2, 5e-2, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0};
}

CallbackHandle& CallbackHandle::operator=(CallbackHandle&& other) noexcept {
  if (this != &other) {
    reset();
    unregister_ = std::move(other.unregister_);
    other.unregister_ = nullptr;
  }
  return *this;
}

void CallbackHandle::reset() {
  if (unregister_) unregister_();
  unregister_ = nullptr;
}

// What a scrape sees: prometheus-cpp's registry (counters, gauges, histograms), the callbacks read now, and
// the process metrics, one family per name in name order. Called with the registry's mutex held.
class MetricsRegistry::Scrape {
 public:
  static std::vector<prometheus::MetricFamily> collect(const MetricsRegistry& r) {
    std::map<std::string, prometheus::MetricFamily> by_name;
    for (auto& f : r.registry_->Collect()) by_name[f.name] = std::move(f);
    for (const auto& [base, f] : r.families_) {
      if (f.callbacks.empty()) continue;
      const std::string name = kMetricPrefix + base;
      auto [it, inserted] = by_name.try_emplace(name);
      if (inserted) {
        it->second.name = name;
        it->second.help = f.help;
        it->second.type = f.type == Type::Counter ? prometheus::MetricType::Counter : prometheus::MetricType::Gauge;
      }
      for (const auto& [labels, cb] : f.callbacks) {
        if (f.gauges.count(labels) || f.counters.count(labels)) continue;  // one sample per label set
        prometheus::ClientMetric m = client_metric(labels);
        if (f.type == Type::Counter) m.counter.value = cb.second();
        else m.gauge.value = cb.second();
        it->second.metric.push_back(std::move(m));
      }
    }
    if (r.with_process_metrics_) {
      for (auto& f : collect_process_metrics()) by_name[f.name] = std::move(f);
    }
    std::vector<prometheus::MetricFamily> out;
    for (auto& [name, f] : by_name) {
      if (f.metric.empty()) continue;
      // prometheus-cpp keeps a family's series in a hash map: sorted by labels, a scrape reads the same way twice.
      std::sort(f.metric.begin(), f.metric.end(), [](const auto& a, const auto& b) { return a.label < b.label; });
      out.push_back(std::move(f));
    }
    return out;
  }
};

MetricsRegistry::MetricsRegistry(bool with_process_metrics)
    : registry_(std::make_shared<prometheus::Registry>()), with_process_metrics_(with_process_metrics) {
  if (with_process_metrics_) {
    gauge("build_info", "Build of this process (value 1): version of the causal twin and of Fast DDS it was built with",
          build_info_labels())
        .set(1.0);
  }
}

MetricsRegistry::~MetricsRegistry() = default;

MetricsRegistry::Family& MetricsRegistry::family(const std::string& name, Type type, const std::string& help,
                                                 const Labels& labels) {
  if (!valid_name(name, false)) throw std::invalid_argument("invalid metric name '" + name + "'");
  if (type == Type::Counter && (name.size() < 6 || name.compare(name.size() - 6, 6, "_total") != 0)) {
    throw std::invalid_argument("counter '" + name + "' must end in _total");
  }
  for (const auto& [k, v] : labels) {
    if (!valid_name(k, true) || k == "le") throw std::invalid_argument("invalid label name '" + k + "' on " + name);
  }
  auto [it, inserted] = families_.try_emplace(name);
  if (inserted) {
    it->second.type = type;
    it->second.help = help;
  } else if (it->second.type != type) {
    throw std::invalid_argument("metric '" + name + "' registered twice with different types");
  }
  return it->second;
}

namespace {

// The metric of `labels` in `slots`, made at first use by `add` from the prometheus family, which `build` (a
// prometheus::Build* builder) registers at the first use of the name.
template <class Metric, class Builder, class Add>
Metric& metric_of(void*& prometheus_family, Builder build, prometheus::Registry& registry, const std::string& name,
                  const std::string& help, std::map<Labels, std::unique_ptr<Metric>>& slots, const Labels& labels,
                  Add add) {
  using PrometheusFamily = std::remove_reference_t<decltype(build.Register(registry))>;
  if (prometheus_family == nullptr) prometheus_family = &build.Name(kMetricPrefix + name).Help(help).Register(registry);
  auto& slot = slots[labels];
  if (!slot) slot = std::make_unique<Metric>(add(*static_cast<PrometheusFamily*>(prometheus_family)));
  return *slot;
}

}  // namespace

Counter& MetricsRegistry::counter(const std::string& name, const std::string& help, const Labels& labels) {
  std::lock_guard<std::mutex> lock(mutex_);
  Family& f = family(name, Type::Counter, help, labels);
  return metric_of(f.prometheus_family, prometheus::BuildCounter(), *registry_, name, help, f.counters, labels,
                   [&](auto& family) -> auto& { return family.Add(labels); });
}

Gauge& MetricsRegistry::gauge(const std::string& name, const std::string& help, const Labels& labels) {
  std::lock_guard<std::mutex> lock(mutex_);
  Family& f = family(name, Type::Gauge, help, labels);
  return metric_of(f.prometheus_family, prometheus::BuildGauge(), *registry_, name, help, f.gauges, labels,
                   [&](auto& family) -> auto& { return family.Add(labels); });
}

Histogram& MetricsRegistry::histogram(const std::string& name, const std::string& help, const Labels& labels,
                                      const std::vector<double>& upper_bounds) {
  for (std::size_t i = 0; i < upper_bounds.size(); ++i) {
    if (!std::isfinite(upper_bounds[i]) || (i > 0 && upper_bounds[i] <= upper_bounds[i - 1])) {
      throw std::invalid_argument("histogram bounds must be finite and strictly increasing");
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  Family& f = family(name, Type::Histogram, help, labels);
  return metric_of(f.prometheus_family, prometheus::BuildHistogram(), *registry_, name, help, f.histograms, labels,
                   [&](auto& family) -> auto& {
                     return family.Add(labels, prometheus::Histogram::BucketBoundaries(upper_bounds));
                   });
}

CallbackHandle MetricsRegistry::gauge_callback(const std::string& name, const std::string& help, const Labels& labels,
                                               std::function<double()> read) {
  return add_callback(name, Type::Gauge, help, labels, std::move(read));
}

CallbackHandle MetricsRegistry::counter_callback(const std::string& name, const std::string& help,
                                                 const Labels& labels, std::function<double()> read) {
  return add_callback(name, Type::Counter, help, labels, std::move(read));
}

CallbackHandle MetricsRegistry::add_callback(const std::string& name, Type type, const std::string& help,
                                             const Labels& labels, std::function<double()> read) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::uint64_t id = next_callback_id_++;
  family(name, type, help, labels).callbacks[labels] = {id, std::move(read)};
  return CallbackHandle([this, name, labels, id] {
    std::lock_guard<std::mutex> relock(mutex_);
    const auto f = families_.find(name);
    if (f == families_.end()) return;
    const auto c = f->second.callbacks.find(labels);
    if (c != f->second.callbacks.end() && c->second.first == id) f->second.callbacks.erase(c);
  });
}

std::string MetricsRegistry::exposition() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return prometheus::TextSerializer().Serialize(Scrape::collect(*this));
}

MetricsRegistry& process_metrics() {
  static MetricsRegistry registry(true);
  return registry;
}

}  // namespace causal::metrics
