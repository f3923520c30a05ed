#include "stage_trace.hpp"

#include "causal/io/time_format.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>

namespace causal::estimator {

std::int64_t StageTrace::now_ns() { return io::utc_now_ns(); }

void StageTrace::keep(std::shared_ptr<Frame> frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  frames_.push_back(std::move(frame));
}

std::size_t StageTrace::rows() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_.size();
}

std::string StageTrace::write() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::FILE* f = std::fopen(path_.c_str(), "w");
  if (f == nullptr) return "cannot open '" + path_ + "' for writing";
  std::fprintf(f, "group,sequence,due_ns,source_ns,received_ns,taken_ns,fed_ns,queued_ns,write_start_ns,write_end_ns,"
                  "queue_depth\n");
  for (const auto& r : frames_) {
    std::fprintf(f, "%s,%llu,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%zu\n", r->group.c_str(),
                 static_cast<unsigned long long>(r->sequence), static_cast<long long>(r->due_ns),
                 static_cast<long long>(r->source_ns), static_cast<long long>(r->received_ns),
                 static_cast<long long>(r->taken_ns), static_cast<long long>(r->fed_ns),
                 static_cast<long long>(r->queued_ns), static_cast<long long>(r->write_start_ns.load()),
                 static_cast<long long>(r->write_end_ns.load()), r->queue_depth);
  }
  const bool ok = std::fclose(f) == 0;
  return ok ? "" : "cannot write '" + path_ + "' (disk full?)";
}

std::string process_cpu_summary(std::uint64_t frames) {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  const double user_s = static_cast<double>(ru.ru_utime.tv_sec) + static_cast<double>(ru.ru_utime.tv_usec) * 1e-6;
  const double sys_s = static_cast<double>(ru.ru_stime.tv_sec) + static_cast<double>(ru.ru_stime.tv_usec) * 1e-6;
  const double per_frame = frames > 0 ? (user_s + sys_s) * 1e6 / static_cast<double>(frames) : 0.0;
  char text[160];
  std::snprintf(text, sizeof text, "user_s=%.3f sys_s=%.3f frames=%llu cpu_per_frame_us=%.1f", user_s, sys_s,
                static_cast<unsigned long long>(frames), per_frame);
  return text;
}

}  // namespace causal::estimator
