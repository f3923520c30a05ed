// The standard process metrics of the Prometheus client libraries (process_cpu_seconds_total,
// process_resident_memory_bytes, process_virtual_memory_bytes, process_start_time_seconds, process_open_fds,
// process_max_fds), read from /proc/self at scrape time: prometheus-cpp 1.0 has no process collector. And the
// labels of causal_twin_build_info. Private to causal_metrics.
#pragma once

#include <prometheus/metric_family.h>

#include <map>
#include <string>
#include <vector>

namespace causal::metrics {

std::vector<prometheus::MetricFamily> collect_process_metrics();

// {version: the causal twin's version, fastdds: the Fast DDS version it was built against}.
std::map<std::string, std::string> build_info_labels();

}  // namespace causal::metrics
