#include "process_metrics.hpp"

#include <dirent.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <sstream>

namespace causal::metrics {

namespace {

prometheus::MetricFamily one(const std::string& name, const std::string& help, prometheus::MetricType type, double v) {
  prometheus::MetricFamily f;
  f.name = name;
  f.help = help;
  f.type = type;
  prometheus::ClientMetric m;
  if (type == prometheus::MetricType::Counter) m.counter.value = v;
  else m.gauge.value = v;
  f.metric.push_back(m);
  return f;
}

// Seconds since the epoch at which the machine booted (/proc/stat btime), 0 when unknown.
double boot_time_s() {
  std::ifstream in("/proc/stat");
  std::string key;
  double value = 0.0;
  while (in >> key) {
    if (key == "btime" && (in >> value)) return value;
    in.ignore(1 << 20, '\n');
  }
  return 0.0;
}

double open_fds() {
  DIR* dir = opendir("/proc/self/fd");
  if (dir == nullptr) return 0.0;
  double n = 0.0;
  while (const dirent* e = readdir(dir)) {
    if (e->d_name[0] != '.') n += 1.0;
  }
  closedir(dir);
  return n - 1.0;  // the descriptor opendir itself holds
}

double max_fds() {
  std::ifstream in("/proc/self/limits");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("Max open files", 0) == 0) {
      std::istringstream fields(line.substr(14));
      double soft = 0.0;
      if (fields >> soft) return soft;
    }
  }
  return 0.0;
}

}  // namespace

std::vector<prometheus::MetricFamily> collect_process_metrics() {
  std::vector<prometheus::MetricFamily> out;
  // /proc/self/stat: the fields after the command name (which may hold spaces) are space-separated; utime and
  // stime are fields 14 and 15, starttime 22 (clock ticks), vsize 23 (bytes), rss 24 (pages).
  std::ifstream in("/proc/self/stat");
  const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return out;
  std::istringstream fields(stat.substr(close + 2));
  std::vector<std::string> f((std::istream_iterator<std::string>(fields)), std::istream_iterator<std::string>());
  if (f.size() < 22) return out;  // f[0] is field 3 (state)
  const double ticks = static_cast<double>(sysconf(_SC_CLK_TCK));
  const double page = static_cast<double>(sysconf(_SC_PAGESIZE));
  const double cpu = (std::stod(f[11]) + std::stod(f[12])) / ticks;
  using prometheus::MetricType;
  out.push_back(one("process_cpu_seconds_total", "Total user and system CPU time spent in seconds.", MetricType::Counter, cpu));
  out.push_back(one("process_max_fds", "Maximum number of open file descriptors.", MetricType::Gauge, max_fds()));
  out.push_back(one("process_open_fds", "Number of open file descriptors.", MetricType::Gauge, open_fds()));
  out.push_back(one("process_resident_memory_bytes", "Resident memory size in bytes.", MetricType::Gauge,
                    std::stod(f[21]) * page));
  out.push_back(one("process_start_time_seconds", "Start time of the process since unix epoch in seconds.",
                    MetricType::Gauge, boot_time_s() + std::stod(f[19]) / ticks));
  out.push_back(one("process_virtual_memory_bytes", "Virtual memory size in bytes.", MetricType::Gauge, std::stod(f[20])));
  return out;
}

std::map<std::string, std::string> build_info_labels() {
  return {{"version", CAUSAL_TWIN_VERSION}, {"fastdds", CAUSAL_TWIN_FASTDDS_VERSION}};
}

}  // namespace causal::metrics
