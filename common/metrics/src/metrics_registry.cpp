#include "causal/metrics/metrics_registry.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace causal::metrics {

namespace {

void atomic_add(std::atomic<double>& a, double by) {
  double old = a.load(std::memory_order_relaxed);
  while (!a.compare_exchange_weak(old, old + by, std::memory_order_relaxed)) {
  }
}

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

// Go's strconv-compatible float text: integers without exponent noise, +Inf/-Inf/NaN spelled as Prometheus does.
std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);  // shortest that reads back exactly, else all 17 digits
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string label_text(const Labels& labels, const std::pair<std::string, std::string>* extra = nullptr) {
  if (labels.empty() && extra == nullptr) return "";
  std::string out = "{";
  const char* sep = "";
  for (const auto& [k, v] : labels) {
    out += sep + k + "=\"" + escape_label_value(v) + "\"";
    sep = ",";
  }
  if (extra != nullptr) out += sep + extra->first + "=\"" + escape_label_value(extra->second) + "\"";
  return out + "}";
}

std::string escape_help(const std::string& help) {
  std::string out;
  for (char c : help) {
    if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

}  // namespace

std::string escape_label_value(const std::string& value) {
  std::string out;
  for (char c : value) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

void Counter::inc(double by) {
  if (!(by >= 0.0) || !std::isfinite(by)) return;
  atomic_add(value_, by);
}

void Gauge::add(double by) {
  if (std::isfinite(by)) atomic_add(value_, by);
}

Histogram::Histogram(std::vector<double> upper_bounds) : bounds_(std::move(upper_bounds)) {
  for (std::size_t i = 0; i < bounds_.size(); ++i) {
    if (!std::isfinite(bounds_[i]) || (i > 0 && bounds_[i] <= bounds_[i - 1])) {
      throw std::invalid_argument("histogram bounds must be finite and strictly increasing");
    }
  }
  counts_ = std::make_unique<std::atomic<std::uint64_t>[]>(bounds_.size() + 1);
  for (std::size_t i = 0; i <= bounds_.size(); ++i) counts_[i].store(0);
}

void Histogram::observe(double v) {
  if (!std::isfinite(v)) return;
  std::size_t i = 0;
  while (i < bounds_.size() && v > bounds_[i]) ++i;  // le: a value equal to a bound falls in that bucket
  counts_[i].fetch_add(1, std::memory_order_relaxed);
  atomic_add(sum_, v);
}

std::vector<std::uint64_t> Histogram::cumulative_counts() const {
  std::vector<std::uint64_t> out(bounds_.size() + 1);
  std::uint64_t running = 0;
  for (std::size_t i = 0; i <= bounds_.size(); ++i) out[i] = running += counts_[i].load(std::memory_order_relaxed);
  return out;
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

Counter& MetricsRegistry::counter(const std::string& name, const std::string& help, const Labels& labels) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& slot = family(name, Type::Counter, help, labels).counters[labels];
  if (!slot) slot = std::make_unique<Counter>();
  return *slot;
}

Gauge& MetricsRegistry::gauge(const std::string& name, const std::string& help, const Labels& labels) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& slot = family(name, Type::Gauge, help, labels).gauges[labels];
  if (!slot) slot = std::make_unique<Gauge>();
  return *slot;
}

Histogram& MetricsRegistry::histogram(const std::string& name, const std::string& help, const Labels& labels,
                                      const std::vector<double>& upper_bounds) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& slot = family(name, Type::Histogram, help, labels).histograms[labels];
  if (!slot) slot = std::make_unique<Histogram>(upper_bounds);
  return *slot;
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
  std::ostringstream out;
  for (const auto& [base, f] : families_) {
    const std::string name = kMetricPrefix + base;
    if (f.counters.empty() && f.gauges.empty() && f.histograms.empty() && f.callbacks.empty()) continue;
    out << "# HELP " << name << " " << escape_help(f.help) << "\n# TYPE " << name << " "
        << (f.type == Type::Counter ? "counter" : f.type == Type::Gauge ? "gauge" : "histogram") << "\n";
    for (const auto& [labels, c] : f.counters) out << name << label_text(labels) << " " << number(c->value()) << "\n";
    for (const auto& [labels, g] : f.gauges) out << name << label_text(labels) << " " << number(g->value()) << "\n";
    for (const auto& [labels, cb] : f.callbacks) {
      if (f.gauges.count(labels) || f.counters.count(labels)) continue;  // one sample per label set
      out << name << label_text(labels) << " " << number(cb.second()) << "\n";
    }
    for (const auto& [labels, h] : f.histograms) {
      const auto counts = h->cumulative_counts();
      for (std::size_t i = 0; i < counts.size(); ++i) {
        const std::pair<std::string, std::string> le{"le", i < h->upper_bounds().size() ? number(h->upper_bounds()[i])
                                                                                           : std::string("+Inf")};
        out << name << "_bucket" << label_text(labels, &le) << " " << counts[i] << "\n";
      }
      out << name << "_sum" << label_text(labels) << " " << number(h->sum()) << "\n";
      out << name << "_count" << label_text(labels) << " " << counts.back() << "\n";
    }
  }
  return out.str();
}

MetricsRegistry& process_metrics() {
  static MetricsRegistry registry;
  return registry;
}

}  // namespace causal::metrics
